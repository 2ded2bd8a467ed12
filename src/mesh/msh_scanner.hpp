// MshScanner: the tokenizer under the Gmsh reader. It walks an MSH file token by token,
// keeps the line number of every token, and turns anything unexpected into a MeshError
// "<path>:<line>: <what>" that names the section being read. Binary MSH files mix ASCII
// lines (section keywords, some counts) with raw little-endian data; after
// use_byte_offsets() every location is the byte offset of the token or value instead
// ("<path>: byte <offset>: <what>"), since lines mean nothing inside binary data.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace dipc {

class MshScanner {
 public:
  // `text` is the whole file; `path` is only used in messages.
  MshScanner(std::string text, std::string path);

  // The section being read ("$Nodes"), named by errors; empty between sections.
  void enter_section(std::string name) { section_ = std::move(name); }

  // False once only whitespace is left.
  bool has_token();
  // The next whitespace-separated token; at end of file it fails with "section is truncated".
  // `expected` says what the caller wants there, for the message.
  std::string_view token(const char* expected);
  std::int64_t integer(const char* expected);
  // Like integer(), but must be >= 0; used for counts and flags.
  std::int64_t count(const char* expected);
  double real(const char* expected);
  // A double-quoted string on the current line (names in $PhysicalNames).
  std::string quoted(const char* expected);
  // Reads the next token and fails unless it is `keyword` (e.g. "$EndNodes").
  void expect(const char* keyword, const char* hint);
  // Skips whole lines up to and including the line "$End<name>" (unknown sections).
  void skip_section(const std::string& name);

  // Binary data. Gmsh writes it right after the newline that ends an ASCII line, so
  // begin_binary() consumes the rest of the current line (only '\r' may precede its '\n');
  // the binary_* readers then take raw bytes, stored little-endian (the reader checks the
  // file's byte order once, in $MeshFormat), and fail with "truncated" at the end of the
  // file.
  void begin_binary(const char* expected);
  std::int64_t binary_int(const char* expected);  // 4-byte signed int
  // An unsigned integer of `bytes` (4 or 8, the file's size_t) that must fit in int64.
  std::int64_t binary_size(int bytes, const char* expected);
  double binary_double(const char* expected);
  // The 4 bytes at the current position, unread (endianness check in $MeshFormat).
  bool peek_bytes(unsigned char out[4]) const;

  // From now on, locations are byte offsets (a binary file).
  void use_byte_offsets() { byte_offsets_ = true; }
  bool byte_offsets() const { return byte_offsets_; }
  // Where the token or value most recently read is: its 1-based line, or its byte offset
  // after use_byte_offsets(). fail_at() takes such a location.
  std::int64_t location() const { return byte_offsets_ ? token_offset_ : token_line_; }
  // Bytes not yet read: an upper bound on how many entries the rest can hold, used to cap
  // reservations taken from counts in the file.
  std::size_t remaining() const { return text_.size() - pos_; }
  const std::string& path() const { return path_; }

  // The version that $MeshFormat declares ("2.2", "4.1"). $Entities, $Nodes and $Elements are
  // laid out differently in 2.2 and 4.1, and a body of the other version mostly parses as
  // numbers of the wrong meaning until a count or flag fails far from the cause; so a
  // "malformed" or "truncated" error in those sections ends with the declared version and asks
  // whether the file is another.
  void declare_version(std::string version) { version_ = std::move(version); }

  [[noreturn]] void fail(const std::string& what) const { fail_at(location(), what); }
  [[noreturn]] void fail_at(std::int64_t location, const std::string& what) const;

 private:
  void skip_whitespace();
  // Marks `n` raw bytes at the current position as the value read, or fails as truncated.
  const unsigned char* take(std::size_t n, const char* expected);
  [[noreturn]] void fail_unexpected(std::string_view found, const char* expected) const;

  std::string text_;
  std::string path_;
  std::string section_;
  std::string version_;  // declared by $MeshFormat; empty before it is read
  std::size_t pos_ = 0;
  std::int64_t line_ = 1;         // line of text_[pos_]
  std::int64_t token_line_ = 1;   // line of the last token
  std::size_t token_offset_ = 0;  // byte offset of the last token or binary value
  bool byte_offsets_ = false;
};

}  // namespace dipc
