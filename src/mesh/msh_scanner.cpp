// MshScanner implementation (see msh_scanner.hpp).
#include "mesh/msh_scanner.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>

#include "mesh/mesh_error.hpp"

namespace dipc {

MshScanner::MshScanner(std::string text, std::string path) : text_(std::move(text)), path_(std::move(path)) {}

void MshScanner::fail_at(std::int64_t location, const std::string& message) const {
  std::string what = message;
  // Only a section's layout failing ("malformed", "truncated") can come from another version;
  // a non-finite coordinate or a tetrahedron says what it is.
  const bool layout = message.find(" is malformed") != std::string::npos ||
                      message.find(" is truncated") != std::string::npos;
  if (layout && !version_.empty() && (section_ == "$Entities" || section_ == "$Nodes" || section_ == "$Elements"))
    what += " (read as MSH " + version_ + ", the version its $MeshFormat declares: is the file another version?)";
  if (byte_offsets_) throw MeshError(path_ + ": byte " + std::to_string(location) + ": " + what);
  throw MeshError(path_ + ":" + std::to_string(location) + ": " + what);
}

void MshScanner::skip_whitespace() {
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (c == '\n') {
      ++line_;
    } else if (c != ' ' && c != '\t' && c != '\r' && c != '\f' && c != '\v') {
      return;
    }
    ++pos_;
  }
}

bool MshScanner::has_token() {
  skip_whitespace();
  return pos_ < text_.size();
}

void MshScanner::fail_unexpected(std::string_view found, const char* expected) const {
  const std::string in = section_.empty() ? std::string("file") : section_ + " section";
  // A '$' keyword where data should be means the section ended early (a count in its header
  // is larger than what follows, or the file was cut).
  if (!found.empty() && found.front() == '$')
    fail(in + " is truncated: found '" + std::string(found) + "' where " + expected + " should be");
  std::string shown(found.substr(0, 40));
  if (found.size() > 40) shown += "...";
  fail(in + " is malformed: expected " + expected + ", found '" + shown + "'");
}

std::string_view MshScanner::token(const char* expected) {
  skip_whitespace();
  if (pos_ >= text_.size()) {
    // Point at the last line that holds anything (the previous token's), not the empty one
    // after the final newline.
    const std::string in = section_.empty() ? std::string("file") : section_ + " section";
    fail(in + " is truncated: the file ends where " + expected + " should be");
  }
  token_line_ = line_;
  token_offset_ = pos_;
  const std::size_t begin = pos_;
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v') break;
    ++pos_;
  }
  return std::string_view(text_).substr(begin, pos_ - begin);
}

std::int64_t MshScanner::integer(const char* expected) {
  const std::string_view t = token(expected);
  std::size_t skip = (!t.empty() && t.front() == '+') ? 1 : 0;
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(t.data() + skip, t.data() + t.size(), value);
  if (ec != std::errc() || end != t.data() + t.size() || t.size() == skip) fail_unexpected(t, expected);
  return value;
}

std::int64_t MshScanner::count(const char* expected) {
  const std::int64_t value = integer(expected);
  if (value < 0) {
    const std::string in = section_.empty() ? std::string("file") : section_ + " section";
    fail(in + " is malformed: " + expected + " is negative (" + std::to_string(value) + ")");
  }
  return value;
}

double MshScanner::real(const char* expected) {
  const std::string_view t = token(expected);
  // std::from_chars (unlike strtod) rejects a leading '+', which hand-written files may have.
  std::size_t skip = (!t.empty() && t.front() == '+') ? 1 : 0;
  double value = 0;
  const auto [end, ec] = std::from_chars(t.data() + skip, t.data() + t.size(), value);
  if (ec != std::errc() || end != t.data() + t.size() || t.size() == skip) fail_unexpected(t, expected);
  return value;
}

std::string MshScanner::quoted(const char* expected) {
  while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t')) ++pos_;
  token_line_ = line_;
  token_offset_ = pos_;
  if (pos_ >= text_.size() || text_[pos_] != '"') {
    const std::size_t end = text_.find_first_of("\r\n", pos_);
    fail_unexpected(std::string_view(text_).substr(pos_, end == std::string::npos ? end : end - pos_), expected);
  }
  const std::size_t close = text_.find_first_of("\"\n", pos_ + 1);
  if (close == std::string::npos || text_[close] != '"') {
    const std::string in = section_.empty() ? std::string("file") : section_ + " section";
    fail(in + " is malformed: " + expected + " has no closing '\"' on its line");
  }
  std::string value = text_.substr(pos_ + 1, close - pos_ - 1);
  pos_ = close + 1;
  return value;
}

void MshScanner::expect(const char* keyword, const char* hint) {
  const std::string_view t = token(keyword);
  if (t != keyword) {
    const std::string in = section_.empty() ? std::string("file") : section_ + " section";
    fail(in + " is malformed: expected " + keyword + ", found '" + std::string(t.substr(0, 40)) + "' (" + hint + ")");
  }
}

void MshScanner::skip_section(const std::string& name) {
  const std::string end = "$End" + name;
  const std::int64_t start = location();
  // Line-wise, not token-wise: unknown sections may hold quoted strings with spaces.
  while (pos_ < text_.size()) {
    const std::size_t eol = text_.find('\n', pos_);
    const std::size_t stop = eol == std::string::npos ? text_.size() : eol;
    std::string_view line = std::string_view(text_).substr(pos_, stop - pos_);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    const bool found = line == end;
    pos_ = stop;
    if (found) {
      token_line_ = line_;
      token_offset_ = pos_;
      return;
    }
    if (eol != std::string::npos) ++pos_, ++line_;
  }
  fail_at(start, "section $" + name + " is not terminated (no " + end + " before the end of the file)");
}

void MshScanner::begin_binary(const char* expected) {
  while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\r')) ++pos_;
  if (pos_ >= text_.size() || text_[pos_] != '\n') {
    token_offset_ = pos_;
    const std::string in = section_.empty() ? std::string("file") : section_ + " section";
    fail(in + " is malformed: expected the end of the line before " + expected);
  }
  ++pos_;
  ++line_;
}

const unsigned char* MshScanner::take(std::size_t n, const char* expected) {
  token_offset_ = pos_;
  if (text_.size() - pos_ < n) {
    const std::string in = section_.empty() ? std::string("file") : section_ + " section";
    fail(in + " is truncated: the file ends where " + expected + " should be");
  }
  const auto* p = reinterpret_cast<const unsigned char*>(text_.data() + pos_);
  pos_ += n;
  return p;
}

namespace {
std::uint64_t little_endian(const unsigned char* p, int bytes) {
  std::uint64_t v = 0;
  for (int b = bytes - 1; b >= 0; --b) v = (v << 8) | p[b];
  return v;
}
}  // namespace

std::int64_t MshScanner::binary_int(const char* expected) {
  const auto v = static_cast<std::uint32_t>(little_endian(take(4, expected), 4));
  return static_cast<std::int32_t>(v);
}

std::int64_t MshScanner::binary_size(int bytes, const char* expected) {
  const std::uint64_t v = little_endian(take(static_cast<std::size_t>(bytes), expected), bytes);
  if (v > static_cast<std::uint64_t>(INT64_MAX)) {
    const std::string in = section_.empty() ? std::string("file") : section_ + " section";
    fail(in + " is malformed: " + expected + " is " + std::to_string(v) + ", out of range");
  }
  return static_cast<std::int64_t>(v);
}

double MshScanner::binary_double(const char* expected) {
  const std::uint64_t bits = little_endian(take(8, expected), 8);
  double v;
  static_assert(sizeof v == sizeof bits, "IEEE-754 binary64 doubles");
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

bool MshScanner::peek_bytes(unsigned char out[4]) const {
  if (text_.size() - pos_ < 4) return false;
  std::memcpy(out, text_.data() + pos_, 4);
  return true;
}

}  // namespace dipc
