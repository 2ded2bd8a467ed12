// MshScanner: the tokenizer under the Gmsh reader. It walks an ASCII MSH file token by token,
// keeps the line number of every token, and turns anything unexpected into a MeshError
// "<path>:<line>: <what>" that names the section being read.
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

  // 1-based line of the token most recently returned.
  std::int64_t line() const { return token_line_; }
  // Bytes not yet read: an upper bound on how many entries the rest can hold, used to cap
  // reservations taken from counts in the file.
  std::size_t remaining() const { return text_.size() - pos_; }
  const std::string& path() const { return path_; }

  [[noreturn]] void fail(const std::string& what) const { fail_at(token_line_, what); }
  [[noreturn]] void fail_at(std::int64_t line, const std::string& what) const;

 private:
  void skip_whitespace();
  [[noreturn]] void fail_unexpected(std::string_view found, const char* expected) const;

  std::string text_;
  std::string path_;
  std::string section_;
  std::size_t pos_ = 0;
  std::int64_t line_ = 1;        // line of text_[pos_]
  std::int64_t token_line_ = 1;  // line of the last token
};

}  // namespace dipc
