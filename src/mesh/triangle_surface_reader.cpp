// OBJ and STL triangle-surface readers (see triangle_surface_reader.hpp).
#include "mesh/triangle_surface_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "math/vector3.hpp"
#include "mesh/mesh_error.hpp"

namespace dipc {

std::string describe_triangle(const TriangleSurface& surface, std::size_t t) {
  const std::int64_t origin = surface.triangle_origin.at(t);
  if (surface.binary) return surface.source + ": facet " + std::to_string(origin);
  return surface.source + ":" + std::to_string(origin);
}

namespace {

std::string read_whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError(path + ": cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw MeshError(path + ": read error");
  return text.str();
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string shown(std::string_view token) {
  std::string s(token.substr(0, 40));
  if (token.size() > 40) s += "...";
  return "'" + s + "'";
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

// Parses all of `t` as a double (a leading '+' allowed); false when it is not one number.
// Non-finite values parse ("nan", "inf") so that the caller can name them as such.
bool parse_real(std::string_view t, double& value) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  return ec == std::errc() && end == t.data() + t.size();
}

bool parse_integer(std::string_view t, std::int64_t& value) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  return ec == std::errc() && end == t.data() + t.size();
}

// The faces of a file before vertex merging: corner ids index `vertices` as read.
struct RawSurface {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;
  std::vector<std::int64_t> origin;
};

// Hash of a coordinate triple by its bits; -0.0 is stored as 0.0 before hashing so that the
// two compare and hash equal.
struct Vec3Hash {
  std::size_t operator()(const Vec3& p) const {
    std::size_t h = 1469598103934665603ull;
    for (double x : p) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
      h ^= h >> 29;
    }
    return h;
  }
};

// Merges equal vertices (first appearance wins the id), drops unused ones and rejects
// degenerate triangles. `where(t)` is the message prefix for raw triangle t.
TriangleSurface finish(const RawSurface& raw, std::string path, bool binary,
                       const std::function<std::string(std::size_t)>& where) {
  TriangleSurface out;
  out.source = std::move(path);
  out.binary = binary;
  std::unordered_map<Vec3, std::int64_t, Vec3Hash> id_of;
  std::vector<std::int64_t> new_id(raw.vertices.size(), -1);
  out.triangles.reserve(raw.triangles.size());
  for (std::size_t t = 0; t < raw.triangles.size(); ++t) {
    Triangle tri;
    for (int k = 0; k < 3; ++k) {
      const std::int64_t v = raw.triangles[t][k];
      if (new_id[v] < 0) {
        Vec3 p = raw.vertices[v];
        for (double& x : p) x = x == 0.0 ? 0.0 : x;  // -0.0 -> 0.0
        const auto [it, inserted] = id_of.emplace(p, static_cast<std::int64_t>(out.vertices.size()));
        if (inserted) out.vertices.push_back(p);
        new_id[v] = it->second;
      }
      tri[k] = new_id[v];
    }
    // Twice the area against the longest side squared: the height over the longest side,
    // relative to that side. Zero for coincident or collinear corners.
    const Vec3& a = out.vertices[tri[0]];
    const Vec3& b = out.vertices[tri[1]];
    const Vec3& c = out.vertices[tri[2]];
    const Vec3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const Vec3 ac{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Vec3 bc{c[0] - b[0], c[1] - b[1], c[2] - b[2]};
    Vec3 n;
    cross3(ab.data(), ac.data(), n.data());
    auto norm2 = [](const Vec3& v) { return squared_norm3(v.data()); };
    const double longest2 = std::max({norm2(ab), norm2(ac), norm2(bc)});
    const double twice_area = std::sqrt(norm2(n));
    if (!(twice_area > 1e-12 * longest2)) {
      std::ostringstream msg;
      msg.precision(17);
      msg << where(t) << "degenerate triangle with corners (" << a[0] << " " << a[1] << " " << a[2] << "), (" << b[0]
          << " " << b[1] << " " << b[2] << "), (" << c[0] << " " << c[1] << " " << c[2] << "): ";
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
        msg << "two of its corners are the same point";
      else
        msg << "area " << 0.5 * twice_area << ", its corners are collinear";
      throw MeshError(msg.str());
    }
    out.triangles.push_back(tri);
  }
  out.triangle_origin = raw.origin;
  return out;
}

// Lines of an ASCII file, split into whitespace-separated tokens.
class LineTokens {
 public:
  explicit LineTokens(const std::string& text) : text_(text) {}
  // Reads the next line (joining lines that end in `continuation`, when non-zero); false at
  // the end of the file. line() is the number of the line's first physical line.
  bool next(char continuation) {
    if (pos_ >= text_.size()) return false;
    tokens_.clear();
    line_ = next_line_;
    bool more = true;
    while (more && pos_ <= text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) end = text_.size();
      std::string_view l(text_.data() + pos_, end - pos_);
      pos_ = end + 1;
      ++next_line_;
      while (!l.empty() && is_space(l.back())) l.remove_suffix(1);
      more = continuation != 0 && !l.empty() && l.back() == continuation;
      if (more) l.remove_suffix(1);
      split(l);
      if (pos_ > text_.size()) break;
    }
    return true;
  }
  std::int64_t line() const { return line_; }
  const std::vector<std::string_view>& tokens() const { return tokens_; }

 private:
  void split(std::string_view l) {
    std::size_t i = 0;
    while (i < l.size()) {
      while (i < l.size() && is_space(l[i])) ++i;
      const std::size_t b = i;
      while (i < l.size() && !is_space(l[i])) ++i;
      if (i > b) tokens_.push_back(l.substr(b, i - b));
    }
  }
  const std::string& text_;
  std::size_t pos_ = 0;
  std::int64_t line_ = 0;
  std::int64_t next_line_ = 1;
  std::vector<std::string_view> tokens_;
};

// OBJ statements that carry nothing a triangle surface needs.
bool obj_ignored(const std::string& keyword) {
  static const char* const kIgnored[] = {"vt",       "vn",         "vp",        "g",      "o",     "s",
                                         "mg",       "usemtl",     "mtllib",    "lod",    "bevel", "c_interp",
                                         "d_interp", "shadow_obj", "trace_obj", "maplib", "usemap"};
  for (const char* k : kIgnored)
    if (keyword == k) return true;
  return false;
}

}  // namespace

TriangleSurface read_obj(const std::string& path) {
  const std::string text = read_whole_file(path);
  auto fail = [&](std::int64_t line, const std::string& what) -> void {
    throw MeshError(path + ":" + std::to_string(line) + ": " + what);
  };
  RawSurface raw;
  // Positive references may point past the vertices read so far; they are checked at the end.
  struct Pending {
    std::int64_t reference;
    std::int64_t line;
  };
  std::vector<Pending> forward;
  LineTokens lines(text);
  while (lines.next('\\')) {
    const auto& tok = lines.tokens();
    if (tok.empty() || tok[0].front() == '#') continue;
    const std::int64_t line = lines.line();
    const std::string keyword(tok[0]);
    if (keyword == "v") {
      if (tok.size() != 4 && tok.size() != 5 && tok.size() != 7)
        fail(line, "vertex needs 3 coordinates (optionally w, or an r g b colour), found " +
                       std::to_string(tok.size() - 1) + " numbers");
      Vec3 p;
      static const char* const kAxis[] = {"x", "y", "z"};
      for (int i = 0; i < 3; ++i) {
        if (!parse_real(tok[1 + i], p[i]))
          fail(line, std::string("vertex ") + kAxis[i] + " coordinate is not a number: " + shown(tok[1 + i]));
        if (!std::isfinite(p[i]))
          fail(line,
               "vertex " + std::to_string(raw.vertices.size() + 1) + " has a non-finite " + kAxis[i] + " coordinate");
      }
      if (tok.size() == 5) {
        double w;
        if (!parse_real(tok[4], w) || w != 1.0)
          fail(line, "vertex weight w must be 1 (rational vertices are not supported), found " + shown(tok[4]));
      }
      raw.vertices.push_back(p);
    } else if (keyword == "f") {
      if (tok.size() < 4) fail(line, "face needs at least 3 corners, found " + std::to_string(tok.size() - 1));
      std::vector<std::int64_t> corner;
      for (std::size_t i = 1; i < tok.size(); ++i) {
        const std::string_view c = tok[i];
        // v, v/vt, v//vn or v/vt/vn: the vertex reference is the part before the first '/';
        // the others must be integers or empty (vt in v//vn) but are not used.
        std::size_t part_begin = 0;
        std::int64_t values[3] = {0, 0, 0};
        int parts = 0;
        while (true) {
          const std::size_t slash = c.find('/', part_begin);
          const std::string_view part = c.substr(part_begin,
                                                 slash == std::string_view::npos ? c.npos : slash - part_begin);
          if (parts == 3) fail(line, "face corner " + shown(c) + " has more than v/vt/vn");
          const bool empty_allowed = parts == 1 && slash != std::string_view::npos;
          if (!(part.empty() && empty_allowed) && !parse_integer(part, values[parts]))
            fail(line, "face corner " + shown(c) + " is not v, v/vt, v//vn or v/vt/vn");
          ++parts;
          if (slash == std::string_view::npos) break;
          part_begin = slash + 1;
        }
        const std::int64_t v = values[0];
        const std::int64_t defined = static_cast<std::int64_t>(raw.vertices.size());
        if (v == 0) fail(line, "face corner " + shown(c) + " refers to vertex 0 (OBJ counts from 1)");
        if (v < 0) {
          if (-v > defined)
            fail(line, "face corner " + shown(c) + " refers to vertex " + std::to_string(v) + " but only " +
                           std::to_string(defined) + " vertices precede it");
          corner.push_back(defined + v);
        } else {
          if (v > defined) forward.push_back({v, line});
          corner.push_back(v - 1);
        }
      }
      for (std::size_t k = 1; k + 1 < corner.size(); ++k) {
        raw.triangles.push_back({corner[0], corner[k], corner[k + 1]});
        raw.origin.push_back(line);
      }
    } else if (obj_ignored(keyword)) {
      continue;
    } else if (keyword == "l" || keyword == "p") {
      fail(line, "OBJ " + std::string(keyword == "l" ? "line" : "point") +
                     " elements are not supported: a triangle surface needs faces ('f')");
    } else if (keyword == "cstype" || keyword == "curv" || keyword == "curv2" || keyword == "surf" ||
               keyword == "deg" || keyword == "bmat" || keyword == "step") {
      fail(line, "OBJ free-form geometry ('" + keyword + "') is not supported: export the surface as polygon faces");
    } else {
      fail(line, "unknown OBJ statement " + shown(tok[0]));
    }
  }
  const std::int64_t total = static_cast<std::int64_t>(raw.vertices.size());
  for (const Pending& p : forward)
    if (p.reference > total)
      fail(p.line, "face refers to vertex " + std::to_string(p.reference) + " but the file has " +
                       std::to_string(total) + " vertices");
  if (raw.triangles.empty()) throw MeshError(path + ": no faces ('f' statements) in the file");
  return finish(raw, path, false, [&](std::size_t t) { return path + ":" + std::to_string(raw.origin[t]) + ": "; });
}

namespace {

std::uint32_t le32(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

// An IEEE-754 binary32 stored little-endian, whatever the host's byte order.
double le_float(const unsigned char* p) {
  const std::uint32_t bits = le32(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

TriangleSurface read_binary_stl(const std::string& text, const std::string& path, std::uint32_t count) {
  RawSurface raw;
  raw.vertices.reserve(3 * std::size_t(count));
  const auto* bytes = reinterpret_cast<const unsigned char*>(text.data());
  auto where = [&](std::size_t facet) {
    return path + ": facet " + std::to_string(facet) + " (byte " + std::to_string(84 + 50 * facet) + "): ";
  };
  static const char* const kAxis[] = {"x", "y", "z"};
  for (std::size_t f = 0; f < count; ++f) {
    const unsigned char* facet = bytes + 84 + 50 * f;
    for (int k = 0; k < 3; ++k) {
      Vec3 p;
      for (int i = 0; i < 3; ++i) {
        p[i] = le_float(facet + 12 + 12 * k + 4 * i);
        if (!std::isfinite(p[i]))
          throw MeshError(where(f) + "corner " + std::to_string(k) + " has a non-finite " + kAxis[i] + " coordinate");
      }
      raw.vertices.push_back(p);
    }
    const std::int64_t b = 3 * static_cast<std::int64_t>(f);
    raw.triangles.push_back({b, b + 1, b + 2});
    raw.origin.push_back(static_cast<std::int64_t>(f));
  }
  return finish(raw, path, true, where);
}

TriangleSurface read_ascii_stl(const std::string& text, const std::string& path) {
  // Tokens with their lines; `solid`/`endsolid` take the rest of their line as a name.
  struct Token {
    std::string_view text;
    std::int64_t line;
  };
  std::vector<Token> tokens;
  {
    LineTokens lines(text);
    while (lines.next(0)) {
      const auto& tok = lines.tokens();
      for (std::size_t i = 0; i < tok.size(); ++i) {
        tokens.push_back({tok[i], lines.line()});
        const std::string k = lower(tok[i]);
        if (k == "solid" || k == "endsolid") break;
      }
    }
  }
  std::size_t i = 0;
  std::int64_t last_line = tokens.empty() ? 1 : tokens.back().line;
  auto fail = [&](std::int64_t line, const std::string& what) -> void {
    throw MeshError(path + ":" + std::to_string(line) + ": " + what);
  };
  auto next = [&](const char* expected) -> const Token& {
    if (i >= tokens.size())
      fail(last_line, std::string("ASCII STL is truncated: the file ends where ") + expected + " should be");
    return tokens[i++];
  };
  auto expect = [&](const char* keyword) {
    const Token& t = next(keyword);
    if (lower(t.text) != keyword)
      fail(t.line, std::string("ASCII STL is malformed: expected '") + keyword + "', found " + shown(t.text));
  };
  auto real = [&](const char* what) {
    const Token& t = next(what);
    double v;
    if (!parse_real(t.text, v))
      fail(t.line, std::string("ASCII STL is malformed: expected a ") + what + ", found " + shown(t.text));
    if (!std::isfinite(v)) fail(t.line, std::string("non-finite ") + what);
    return v;
  };
  RawSurface raw;
  expect("solid");
  while (true) {
    const Token& t = next("'facet' or 'endsolid'");
    const std::string k = lower(t.text);
    if (k == "endsolid") {
      if (i == tokens.size()) break;
      expect("solid");  // files that hold several solids
      continue;
    }
    if (k != "facet") fail(t.line, "ASCII STL is malformed: expected 'facet' or 'endsolid', found " + shown(t.text));
    expect("normal");
    for (int n = 0; n < 3; ++n) real("normal component");
    expect("outer");
    expect("loop");
    std::int64_t facet_line = 0;
    for (int c = 0; c < 3; ++c) {
      const Token& v = next("'vertex'");
      if (lower(v.text) != "vertex") {
        if (lower(v.text) == "endloop")
          fail(v.line, "facet has " + std::to_string(c) + " vertices; STL facets are triangles");
        fail(v.line, "ASCII STL is malformed: expected 'vertex', found " + shown(v.text));
      }
      if (c == 0) facet_line = v.line;
      const Vec3 p{real("vertex x coordinate"), real("vertex y coordinate"), real("vertex z coordinate")};
      raw.vertices.push_back(p);
    }
    {
      const Token& e = next("'endloop'");
      if (lower(e.text) == "vertex") fail(e.line, "facet has more than 3 vertices; STL facets are triangles");
      if (lower(e.text) != "endloop")
        fail(e.line, "ASCII STL is malformed: expected 'endloop', found " + shown(e.text));
    }
    expect("endfacet");
    const std::int64_t b = static_cast<std::int64_t>(raw.vertices.size()) - 3;
    raw.triangles.push_back({b, b + 1, b + 2});
    raw.origin.push_back(facet_line);
  }
  if (raw.triangles.empty()) throw MeshError(path + ": no facets in the file");
  return finish(raw, path, false, [&](std::size_t t) { return path + ":" + std::to_string(raw.origin[t]) + ": "; });
}

}  // namespace

TriangleSurface read_stl(const std::string& path) {
  const std::string text = read_whole_file(path);
  if (text.size() >= 84) {
    const std::uint32_t count = le32(reinterpret_cast<const unsigned char*>(text.data()) + 80);
    if (text.size() == 84 + 50 * std::uint64_t(count)) {
      if (count == 0) throw MeshError(path + ": binary STL with no facets");
      return read_binary_stl(text, path, count);
    }
  }
  std::size_t b = 0;
  while (b < text.size() && is_space(text[b])) ++b;
  if (lower(std::string_view(text).substr(b, 5)) == "solid" && (b + 5 == text.size() || is_space(text[b + 5])))
    return read_ascii_stl(text, path);
  if (text.size() < 84)
    throw MeshError(path + ": not an STL file: " + std::to_string(text.size()) +
                    " bytes, too short for binary STL, and it does not start with 'solid'");
  const std::uint32_t count = le32(reinterpret_cast<const unsigned char*>(text.data()) + 80);
  throw MeshError(path + ": not an STL file: binary STL with " + std::to_string(count) + " facets (byte 80) must be " +
                  std::to_string(84 + 50 * std::uint64_t(count)) + " bytes, the file has " +
                  std::to_string(text.size()) + ", and it does not start with 'solid' (ASCII STL)");
}

TriangleSurface read_triangle_surface(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  const std::string ext = dot == std::string::npos || (slash != std::string::npos && dot < slash)
                              ? std::string()
                              : lower(std::string_view(path).substr(dot + 1));
  if (ext == "obj") return read_obj(path);
  if (ext == "stl") return read_stl(path);
  throw MeshError(path + ": unknown surface file extension '" + ext +
                  "' (triangle surfaces are read from .obj or .stl files)");
}

}  // namespace dipc
