#include "support/view_page_data.h"

namespace harmonia::testing {

nlohmann::json view_page_data(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"harmonia-data\">";
  const std::size_t begin = page.find(open);
  if (begin == std::string::npos) return nullptr;
  const std::size_t from = begin + open.size();
  const std::size_t end = page.find("</script>", from);
  if (end == std::string::npos) return nullptr;
  // The writer escapes every "<" inside the element as \u003c, which JSON reads back as "<".
  return nlohmann::json::parse(page.substr(from, end - from));
}

std::vector<unsigned char> base64_decoded(const std::string& text) {
  std::vector<unsigned char> bytes;
  std::uint32_t bits = 0;
  int count = 0;
  for (const char c : text) {
    int value = -1;
    if (c >= 'A' && c <= 'Z') value = c - 'A';
    else if (c >= 'a' && c <= 'z') value = c - 'a' + 26;
    else if (c >= '0' && c <= '9') value = c - '0' + 52;
    else if (c == '+') value = 62;
    else if (c == '/') value = 63;
    if (value < 0) continue;
    bits = (bits << 6) | static_cast<std::uint32_t>(value);
    count += 6;
    if (count >= 8) {
      count -= 8;
      bytes.push_back(static_cast<unsigned char>((bits >> count) & 0xFF));
    }
  }
  return bytes;
}

}  // namespace harmonia::testing
