#include "host/detail/text_scanner.h"

#include <cstring>

#include "host/detail/io_support.h"

namespace harmonia::detail {

TextScanner::TextScanner(std::string_view text, std::string_view file_name)
    : begin_(text.data()), cursor_(text.data()), end_(text.data() + text.size()),
      file_name_(file_name) {
  // A UTF-8 byte order mark is not part of the first line's content.
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") cursor_ += 3;
}

bool TextScanner::continues_line() {
  const char* look = cursor_ + 1;
  while (look != end_ && is_blank(*look)) ++look;
  if (look == end_ || *look != '\n') return false;
  cursor_ = look + 1;
  ++line_;
  return true;
}

std::int64_t TextScanner::last_line() const {
  std::int64_t lines = line_;
  for (const char* look = cursor_; look != end_; ++look) lines += *look == '\n' ? 1 : 0;
  const bool final_newline = end_ != begin_ && end_[-1] == '\n';
  return final_newline && lines > 1 ? lines - 1 : lines;
}

void TextScanner::next_line() {
  const void* newline = std::memchr(cursor_, '\n', static_cast<std::size_t>(end_ - cursor_));
  if (newline == nullptr) {
    cursor_ = end_;
    return;
  }
  cursor_ = static_cast<const char*>(newline) + 1;
  ++line_;
}

bool TextScanner::skip_empty_lines() {
  while (!at_end()) {
    if (!at_line_end()) return true;
    next_line();
  }
  return false;
}

std::string_view TextScanner::read_word() {
  skip_blanks();
  const char* start = cursor_;
  while (!at_separator()) ++cursor_;
  return {start, static_cast<std::size_t>(cursor_ - start)};
}

std::string TextScanner::token_here() const {
  const char* stop = cursor_;
  while (stop != end_ && !is_blank(*stop) && *stop != '\n') ++stop;
  return printable({cursor_, static_cast<std::size_t>(stop - cursor_)});
}

double TextScanner::read_double(std::string_view what) {
  if (at_line_end()) fail("expected " + std::string(what) + ", found the end of the line");
  const char* start = cursor_;
  if (*start == '+' && start + 1 != end_ && start[1] != '-') ++start;  // from_chars rejects '+'.
  double value = 0.0;
  const auto [stop, error] = std::from_chars(start, end_, value);
  if (error == std::errc() || error == std::errc::result_out_of_range) {
    const char* const saved = cursor_;
    cursor_ = stop;
    if (at_separator()) {
      if (error == std::errc()) return value;
      cursor_ = saved;
      fail("number '" + token_here() + "' (" + std::string(what) + ") is out of range");
    }
    cursor_ = saved;
  }
  fail("expected " + std::string(what) + ", found '" + token_here() + "'");
}

bool TextScanner::try_read_integer(std::int64_t& value) {
  const char* start = cursor_;
  if (start != end_ && *start == '+') ++start;
  const auto [stop, error] = std::from_chars(start, end_, value);
  if (error == std::errc::result_out_of_range) fail("integer '" + token_here() + "' is out of range");
  if (error != std::errc()) return false;
  cursor_ = stop;
  return true;
}

std::int64_t TextScanner::read_integer(std::string_view what) {
  if (at_line_end()) fail("expected " + std::string(what) + ", found the end of the line");
  const char* const saved = cursor_;
  std::int64_t value = 0;
  if (try_read_integer(value) && at_separator()) return value;
  cursor_ = saved;
  fail("expected " + std::string(what) + " (an integer), found '" + token_here() + "'");
}

void TextScanner::skip_numbers(std::string_view what) {
  while (!at_line_end()) read_double(what);
}

void TextScanner::expect_line_end(std::string_view context) {
  if (!at_line_end()) {
    fail("unexpected '" + token_here() + "' after " + std::string(context));
  }
}

void TextScanner::fail(std::string_view problem) const { throw_at_line(file_name_, line_, problem); }

}  // namespace harmonia::detail
