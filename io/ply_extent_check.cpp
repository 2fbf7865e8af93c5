#include "io/ply_extent_check.h"

#include <cstdint>
#include <limits>
#include <sstream>
#include <string_view>

namespace fq::io {

namespace {

struct Property {
  int size = 0;        ///< bytes of a value (of a list item for lists)
  int count_size = 0;  ///< bytes of a list's count; 0 for plain properties
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

/// Byte size of a PLY scalar type, 0 when unknown.
int type_size(const std::string& t) {
  if (t == "char" || t == "int8" || t == "uchar" || t == "uint8") return 1;
  if (t == "short" || t == "int16" || t == "ushort" || t == "uint16") return 2;
  if (t == "int" || t == "int32" || t == "uint" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

/// Parses the header; false when it is not a binary little-endian header we understand.
bool parse_header(const std::vector<char>& bytes, std::vector<Element>& elements, size_t& body) {
  constexpr std::string_view kEnd = "end_header\n";
  const std::string_view all(bytes.data(), bytes.size());
  const size_t end = all.find(kEnd);
  if (end == std::string_view::npos) return false;
  body = end + kEnd.size();
  std::istringstream header(std::string(all.substr(0, end)));
  bool binary_le = false;
  for (std::string line; std::getline(header, line);) {
    std::istringstream words(line);
    std::string key, a, b, c;
    words >> key;
    if (key == "format") {
      words >> a;
      binary_le = a == "binary_little_endian";
    } else if (key == "element") {
      elements.push_back({});
      if (!(words >> elements.back().name >> elements.back().count)) return false;
    } else if (key == "property") {
      if (elements.empty() || !(words >> a)) return false;
      Property p;
      if (a == "list") {
        if (!(words >> b >> c)) return false;
        p = {type_size(c), type_size(b)};
        if (p.count_size == 0) return false;
      } else {
        p.size = type_size(a);
      }
      if (p.size == 0) return false;
      elements.back().properties.push_back(p);
    }
  }
  return binary_le;
}

uint64_t read_count(const char* p, int size) {
  uint64_t v = 0;
  for (int i = 0; i < size; ++i) v |= uint64_t(static_cast<unsigned char>(p[i])) << (8 * i);
  return v;
}

/// Advances `at` over one element's data; false when the file ends first.
bool skip_element(const std::vector<char>& bytes, const Element& e, size_t& at) {
  const size_t size = bytes.size();
  bool has_list = false;
  uint64_t row = 0;
  for (const Property& p : e.properties) {
    has_list |= p.count_size > 0;
    row += p.size;
  }
  if (!has_list) {
    if (row > 0 && e.count > (size - at) / row) return false;
    at += e.count * row;
    return true;
  }
  for (uint64_t i = 0; i < e.count; ++i) {
    for (const Property& p : e.properties) {
      if (p.count_size == 0) {
        if (size - at < size_t(p.size)) return false;
        at += p.size;
        continue;
      }
      if (size - at < size_t(p.count_size)) return false;
      const uint64_t n = read_count(bytes.data() + at, p.count_size);
      at += p.count_size;
      if (n > (size - at) / p.size) return false;
      at += n * p.size;
    }
  }
  return true;
}

}  // namespace

Status check_binary_ply_extent(const std::string& path, const std::vector<char>& bytes) {
  std::vector<Element> elements;
  size_t at = 0;
  if (!parse_header(bytes, elements, at)) return {};
  for (const Element& e : elements) {
    if (e.count > uint64_t(std::numeric_limits<int32_t>::max()))
      return invalid_input("cannot decode '" + path + "': element '" + e.name + "' has " +
                           std::to_string(e.count) + " entries (at most 2^31 - 1 are supported)");
    if (!skip_element(bytes, e, at))
      return invalid_input("cannot decode '" + path + "': file is truncated (the header announces " +
                           std::to_string(e.count) + " " + e.name + " entries, the data ends before them)");
  }
  return {};
}

}  // namespace fq::io
