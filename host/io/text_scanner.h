#pragma once
// A forward-only scanner over the text of a whole file, for the line-oriented mesh formats (OBJ,
// OFF, ASCII PLY, ASCII STL). It knows the current line number so that every error can say where it
// is, parses numbers with std::from_chars (no locale, no allocation, no iostreams) and treats `\r`,
// tabs, trailing blanks, `# comments` and backslash-newline continuations as separators.

#include <charconv>
#include <concepts>
#include <cstdint>
#include <string>
#include <string_view>

namespace harmonia::detail {

class TextScanner {
 public:
  //! `file_name` is only used in error messages.
  TextScanner(std::string_view text, std::string_view file_name);

  //! 1-based number of the line the scanner is on.
  [[nodiscard]] std::int64_t line() const { return line_; }
  [[nodiscard]] bool at_end() const { return cursor_ == end_; }
  [[nodiscard]] std::string_view file_name() const { return file_name_; }
  //! Number of the file's last line (a final newline does not start another line).
  [[nodiscard]] std::int64_t last_line() const;
  //! Byte offset of the scanner in the text (where a binary part of a file starts).
  [[nodiscard]] std::size_t offset() const { return static_cast<std::size_t>(cursor_ - begin_); }

  //! Skips blanks (and a backslash-newline continuation) on the current line.
  void skip_blanks() {
    for (;;) {
      while (cursor_ != end_ && is_blank(*cursor_)) ++cursor_;
      if (cursor_ != end_ && *cursor_ == '\\' && continues_line()) continue;
      return;
    }
  }
  //! True when nothing but blanks and a comment is left on the current line (or the file ended).
  [[nodiscard]] bool at_line_end() {
    skip_blanks();
    return cursor_ == end_ || *cursor_ == '\n' || *cursor_ == '#';
  }
  //! Moves to the start of the next line, discarding what is left of this one.
  void next_line();
  //! Moves past lines that hold nothing but blanks or comments. Returns false at the end of file.
  bool skip_empty_lines();

  //! The next blank-separated word on this line (empty at the end of the line).
  std::string_view read_word();
  //! What is left of this line up to a comment, without leading and trailing blanks (a name that
  //! may hold spaces: `usemtl Material 1`). The scanner stays on this line.
  std::string_view rest_of_line();
  //! Reads the next number on this line; false (and nothing consumed) if there is none or it is
  //! malformed. Non-finite values ("nan", "inf") are accepted, so that the caller can name the
  //! vertex that holds them.
  bool try_read_double(double& value);
  //! The same for an integer.
  bool try_read_integer(std::int64_t& value);
  //! Reads an integer that starts exactly under the cursor, whatever follows it (OBJ's `v/vt/vn`).
  bool read_integer_prefix(std::int64_t& value);

  //! The next number on this line; fails naming `what` if it is missing or malformed.
  double read_double(std::string_view what) {
    return read_double([what] { return std::string(what); });
  }
  //! The same, with the description built only on failure (for hot loops).
  template <std::invocable Describe>
  double read_double(const Describe& describe) {
    double value = 0.0;
    if (!try_read_double(value)) number_error(describe(), false);
    return value;
  }
  //! The next integer on this line; fails naming `what` if it is missing or malformed.
  std::int64_t read_integer(std::string_view what) {
    return read_integer([what] { return std::string(what); });
  }
  template <std::invocable Describe>
  std::int64_t read_integer(const Describe& describe) {
    std::int64_t value = 0;
    if (!try_read_integer(value)) number_error(describe(), true);
    return value;
  }
  //! Reads any remaining numbers on the line (colours, normals, w), checking that they are numbers.
  template <std::invocable Describe>
  void skip_numbers(const Describe& describe) {
    double ignored = 0.0;
    while (!at_line_end()) {
      if (!try_read_double(ignored)) number_error(describe(), false);
    }
  }
  void skip_numbers(std::string_view what) {
    skip_numbers([what] { return std::string(what); });
  }
  //! Fails unless only blanks or a comment remain on the line.
  void expect_line_end(std::string_view context);
  //! The character under the cursor ('\0' at the end of file).
  [[nodiscard]] char peek() const { return cursor_ == end_ ? '\0' : *cursor_; }
  void advance() { ++cursor_; }
  //! True when the cursor is at a place where a token may end.
  [[nodiscard]] bool at_separator() const {
    return cursor_ == end_ || is_blank(*cursor_) || *cursor_ == '\n' || *cursor_ == '#' ||
           *cursor_ == '\\';
  }

  //! Throws Error(parse_error, "FILE:LINE: problem") for the current line.
  [[noreturn]] void fail(std::string_view problem) const;
  //! Same, naming the file's last line (for "the file ends ..." and "no faces" problems).
  [[noreturn]] void fail_at_end(std::string_view problem) const;
  //! The next token on the line (not consumed), made printable, for "found '...'" messages.
  [[nodiscard]] std::string token_here() {
    skip_blanks();
    return token_at(offset());
  }
  //! The token that starts at byte `offset`, made printable.
  [[nodiscard]] std::string token_at(std::size_t offset) const;

 private:
  static bool is_blank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
  }
  // Fails with "expected WHAT, found ..." for the token under the cursor.
  [[noreturn]] void number_error(const std::string& what, bool integer);
  // A backslash followed only by blanks up to the end of the line joins the next line to this one.
  bool continues_line();

  const char* begin_;
  const char* cursor_;
  const char* end_;
  std::int64_t line_ = 1;
  std::string_view file_name_;
};

}  // namespace harmonia::detail
