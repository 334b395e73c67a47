#pragma once
// The data of a page that harmonia::write_view_page wrote, read back independently of the writer:
// the JSON of its data element, and its base64 arrays decoded.

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace harmonia::testing {

//! The JSON inside <script type="application/json" id="harmonia-data"> (null when absent).
nlohmann::json view_page_data(const std::string& page);

//! RFC 4648 base64, decoded (padding and characters outside the alphabet skipped).
std::vector<unsigned char> base64_decoded(const std::string& text);

//! A base64 string of a page's data read as an array of T (little-endian, as the page reads it).
template <typename T>
std::vector<T> view_page_array(const nlohmann::json& text) {
  const std::vector<unsigned char> bytes = base64_decoded(text.get<std::string>());
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

}  // namespace harmonia::testing
