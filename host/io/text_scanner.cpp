#include "io/text_scanner.h"

#include <cstring>

#include "io/io_support.h"

namespace harmonia::detail {

TextScanner::TextScanner(std::string_view text, std::string_view file_name)
    : begin_(text.data()),
      cursor_(text.data()),
      end_(text.data() + text.size()),
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

std::string_view TextScanner::rest_of_line() {
  skip_blanks();
  const char* start = cursor_;
  while (cursor_ != end_ && *cursor_ != '\n' && *cursor_ != '#') ++cursor_;
  const char* stop = cursor_;
  while (stop != start && (is_blank(stop[-1]) || stop[-1] == '\r')) --stop;
  return {start, static_cast<std::size_t>(stop - start)};
}

std::string TextScanner::token_at(std::size_t offset) const {
  const char* const start = begin_ + offset;
  const char* stop = start;
  while (stop != end_ && !is_blank(*stop) && *stop != '\n') ++stop;
  return printable({start, static_cast<std::size_t>(stop - start)});
}

namespace {

// std::from_chars does not accept a leading '+'; skip one (but not "+-").
const char* skip_plus(const char* start, const char* end) {
  return start != end && *start == '+' && start + 1 != end && start[1] != '-' ? start + 1 : start;
}

}  // namespace

bool TextScanner::try_read_double(double& value) {
  if (at_line_end()) return false;
  const char* const saved = cursor_;
  const auto [stop, error] = std::from_chars(skip_plus(cursor_, end_), end_, value);
  if (error != std::errc()) return false;
  cursor_ = stop;
  if (at_separator()) return true;
  cursor_ = saved;
  return false;
}

bool TextScanner::read_integer_prefix(std::int64_t& value) {
  const auto [stop, error] = std::from_chars(skip_plus(cursor_, end_), end_, value);
  if (error == std::errc::result_out_of_range) {
    fail("integer '" + token_here() + "' is out of range");
  }
  if (error != std::errc()) return false;
  cursor_ = stop;
  return true;
}

bool TextScanner::try_read_integer(std::int64_t& value) {
  if (at_line_end()) return false;
  const char* const saved = cursor_;
  if (read_integer_prefix(value) && at_separator()) return true;
  cursor_ = saved;
  return false;
}

void TextScanner::number_error(const std::string& what, bool integer) {
  if (at_line_end()) fail("expected " + what + ", found the end of the line");
  // Tell a number too large for its type from a token that is no number at all.
  const char* const start = skip_plus(cursor_, end_);
  double as_double = 0.0;
  std::int64_t as_integer = 0;
  const auto [stop, error] =
      integer ? std::from_chars(start, end_, as_integer) : std::from_chars(start, end_, as_double);
  const char* const saved = cursor_;
  cursor_ = stop;
  const bool whole_token = at_separator();
  cursor_ = saved;
  if (error == std::errc::result_out_of_range && whole_token) {
    fail("number '" + token_here() + "' (" + what + ") is out of range");
  }
  fail("expected " + what + (integer ? " (an integer)" : "") + ", found '" + token_here() + "'");
}

void TextScanner::expect_line_end(std::string_view context) {
  if (!at_line_end()) {
    fail("unexpected '" + token_here() + "' after " + std::string(context));
  }
}

void TextScanner::fail(std::string_view problem) const {
  throw_at_line(file_name_, line_, problem);
}

void TextScanner::fail_at_end(std::string_view problem) const {
  throw_at_line(file_name_, last_line(), problem);
}

}  // namespace harmonia::detail
