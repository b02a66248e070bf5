#include "slicer/ply.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "slicer/triangulate.hpp"

namespace beadtwin::slicer {

namespace {

enum class Type : std::uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

// The header's type names: the original ones and the sized ones most writers use now.
std::optional<Type> type_named(std::string_view name) {
  static constexpr std::pair<std::string_view, Type> kNames[] = {
      {"char", Type::kInt8},      {"int8", Type::kInt8},       {"uchar", Type::kUint8},
      {"uint8", Type::kUint8},    {"short", Type::kInt16},     {"int16", Type::kInt16},
      {"ushort", Type::kUint16},  {"uint16", Type::kUint16},   {"int", Type::kInt32},
      {"int32", Type::kInt32},    {"uint", Type::kUint32},     {"uint32", Type::kUint32},
      {"float", Type::kFloat32},  {"float32", Type::kFloat32}, {"double", Type::kFloat64},
      {"float64", Type::kFloat64}};
  for (const auto& [n, t] : kNames)
    if (n == name) return t;
  return std::nullopt;
}

std::size_t size_of(Type t) {
  switch (t) {
    case Type::kInt8:
    case Type::kUint8:
      return 1;
    case Type::kInt16:
    case Type::kUint16:
      return 2;
    case Type::kInt32:
    case Type::kUint32:
    case Type::kFloat32:
      return 4;
    case Type::kFloat64:
      return 8;
  }
  return 8;
}

bool is_integer(Type t) {
  return t != Type::kFloat32 && t != Type::kFloat64;
}

struct Property {
  std::string name;
  Type type = Type::kFloat32;      // of the value, or of a list's entries
  std::optional<Type> count_type;  // a list's count; none for a single value
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  int line = 0;  // its header line
  std::vector<Property> properties;
};

enum class Format : std::uint8_t { kAscii, kLittleEndian, kBigEndian };

struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  std::size_t data_start = 0;  // the first byte after end_header's line
  int lines = 0;               // the header's lines, end_header's included
};

std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

bool is_count(std::string_view w) {
  return !w.empty() && w.size() <= 10 &&
         std::all_of(w.begin(), w.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// The header, line by line: "ply", then lines of words (separated by spaces or tabs) each starting comment,
// obj_info, format, element or property, and last "end_header". At most 64 KB.
Header read_header(const std::string& file, std::string_view data) {
  constexpr std::size_t kMaxHeader = 64 * 1024;
  const std::string_view head = data.substr(0, kMaxHeader);
  Header h;
  bool format = false;
  std::size_t pos = 0;
  for (int number = 1; pos < head.size(); ++number) {
    const std::size_t eol = head.find('\n', pos);
    if (eol == std::string_view::npos) break;  // the header's last line is cut off
    std::string_view line = head.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const auto fail = [&](const std::string& what) { throw InputError({file, number, 1}, {}, what); };
    if (number == 1) {
      if (line != "ply") fail("not a PLY: its first line is not \"ply\"");
      continue;
    }
    const std::vector<std::string_view> w = words_of(line);
    if (w.empty()) fail("an empty line in the PLY header");
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        fail(
            fmt::format("PLY format '{}': expected format ascii, binary_little_endian or binary_big_endian "
                        "and a version",
                        w.size() > 1 ? w[1] : ""));
      h.format = w[1] == "ascii"                  ? Format::kAscii
                 : w[1] == "binary_little_endian" ? Format::kLittleEndian
                                                  : Format::kBigEndian;
      format = true;
    } else if (w[0] == "element") {
      if (w.size() != 3 || !is_count(w[2])) fail("a PLY element line: expected element NAME COUNT");
      for (const Element& e : h.elements)
        if (e.name == w[1])
          fail(fmt::format("a second PLY element '{}' (the first is on line {})", w[1], e.line));
      h.elements.push_back({std::string(w[1]), std::stoull(std::string(w[2])), number, {}});
    } else if (w[0] == "property") {
      const bool list = w.size() == 5 && w[1] == "list" && type_named(w[2]) && type_named(w[3]);
      if (!list && !(w.size() == 3 && type_named(w[1])))
        fail(
            "a PLY property line: expected property TYPE NAME or property list TYPE TYPE NAME, with the "
            "types char, uchar, short, ushort, int, uint, float, double (or int8 ... float64)");
      if (h.elements.empty()) fail("a PLY property line before any element line");
      Element& e = h.elements.back();
      Property p{std::string(w.back()), *type_named(w[list ? 3 : 1]), std::nullopt};
      if (list) {
        p.count_type = type_named(w[2]);
        if (!is_integer(*p.count_type))
          fail(fmt::format("a PLY list's count is a whole number: its type cannot be {}", w[2]));
      }
      for (const Property& q : e.properties)
        if (q.name == p.name)
          fail(fmt::format("PLY element '{}' has a second property '{}'", e.name, p.name));
      e.properties.push_back(std::move(p));
    } else if (w[0] == "end_header") {
      if (w.size() != 1) fail("the PLY end_header line has more on it");
      if (!format) fail("the PLY header has no format line");
      h.data_start = pos;
      h.lines = number;
      return h;
    } else {
      fail(
          fmt::format("PLY header: '{}' is not a header line; expected comment, format, element, property or "
                      "end_header",
                      std::string(w[0]).substr(0, 40)));
    }
  }
  throw InputError({file, 0, 0}, {},
                   head.size() < kMaxHeader
                       ? std::string("not a PLY: its header has no end_header line")
                       : fmt::format("not a PLY: no end_header line in its first {} KB", kMaxHeader / 1024));
}

// The data of an ASCII PLY: an element to a line, numbers separated by spaces or tabs. Blank lines are
// stepped over. Messages give the line and column.
class TextData {
 public:
  TextData(const std::string& file, std::string_view data, const Header& h)
      : file_(file), data_(data), pos_(h.data_start), line_number_(h.lines) {}

  std::size_t remaining() const { return data_.size() - pos_ + 1; }  // the last line may have no newline
  // The fewest bytes an element of `e` takes: a digit and a separator for each value and list count.
  static std::size_t least_bytes(const Element& e) { return 2 * e.properties.size(); }

  // Moves to instance `i` of `e` (counted from 0): the next line that is not blank.
  void begin(const Element& e, std::uint64_t i) {
    element_ = &e;
    for (;;) {
      if (pos_ >= data_.size())
        throw InputError({file_, line_number_ + 1, 0}, {},
                         fmt::format("the file ends after {} of the {} '{}' elements its header counts", i,
                                     e.count, e.name));
      const std::size_t eol = std::min(data_.find('\n', pos_), data_.size());
      line_ = data_.substr(pos_, eol - pos_);
      pos_ = std::min(eol + 1, data_.size());
      ++line_number_;
      if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
      column_ = 0;
      skip_blanks();
      if (column_ < line_.size()) return;
    }
  }

  // The next number on the line: property `p`'s value or list count (entry -1) or its list's entry `entry`,
  // of type `t`.
  double value(const Property& p, Type, long long entry) {
    skip_blanks();
    token_column_ = column_;
    if (column_ >= line_.size())
      fail(entry < 0 ? fmt::format("the line ends before {} '{}' has its property '{}'", element_->name,
                                   element_->name, p.name)
                     : fmt::format("the list '{}' counts {} entries, but the line ends after {}", p.name,
                                   list_entries_, entry));
    const std::size_t start = column_;
    while (column_ < line_.size() && line_[column_] != ' ' && line_[column_] != '\t') ++column_;
    std::string_view token = line_.substr(start, column_ - start);
    const std::string_view whole = token;
    if (token.size() > 1 && token.front() == '+') token.remove_prefix(1);  // from_chars takes no plus sign
    double v = 0.0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (end != token.data() + token.size() || (ec != std::errc() && ec != std::errc::result_out_of_range))
      fail(fmt::format("'{}' is not a number (property '{}' of element '{}')", whole.substr(0, 40), p.name,
                       element_->name));
    if (ec == std::errc::result_out_of_range)  // beyond double: strtod says infinity or zero
      v = std::strtod(std::string(token).c_str(), nullptr);
    return v;
  }

  // Starts a list of `n` entries. Nothing to check before they are read: the line ends first.
  void check_list(const Property&, std::uint64_t n) { list_entries_ = n; }

  // Ends the element: nothing may be left on its line.
  void end() {
    skip_blanks();
    if (column_ < line_.size())
      fail(fmt::format("more numbers on the line than element '{}' has properties ({})", element_->name,
                       element_->properties.size()));
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError({file_, line_number_, static_cast<int>(token_column_) + 1}, {}, what);
  }

 private:
  void skip_blanks() {
    while (column_ < line_.size() && (line_[column_] == ' ' || line_[column_] == '\t')) ++column_;
    token_column_ = column_;
  }

  const std::string& file_;
  std::string_view data_;
  std::size_t pos_;
  int line_number_;
  std::string_view line_;
  std::size_t column_ = 0, token_column_ = 0;
  const Element* element_ = nullptr;
  std::uint64_t list_entries_ = 0;  // of the list being read
};

// The data of a binary PLY: the values packed in the header's order, in its byte order. Messages give the
// element and the byte offset.
class BinaryData {
 public:
  BinaryData(const std::string& file, std::string_view data, const Header& h)
      : file_(file),
        data_(data),
        pos_(h.data_start),
        swap_((h.format == Format::kBigEndian) != (std::endian::native == std::endian::big)) {}

  std::size_t remaining() const { return data_.size() - pos_; }
  static std::size_t least_bytes(const Element& e) {
    std::size_t n = 0;
    for (const Property& p : e.properties) n += size_of(p.count_type ? *p.count_type : p.type);
    return n;
  }

  void begin(const Element& e, std::uint64_t i) {
    element_ = &e;
    index_ = i;
  }

  double value(const Property& p, Type t, long long) {
    const std::size_t n = size_of(t);
    value_pos_ = pos_;
    if (remaining() < n) fail(fmt::format("the file ends inside it (property '{}')", p.name));
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    if (swap_) std::reverse(b, b + n);
    switch (t) {
      case Type::kInt8:
        return read<std::int8_t>(b);
      case Type::kUint8:
        return read<std::uint8_t>(b);
      case Type::kInt16:
        return read<std::int16_t>(b);
      case Type::kUint16:
        return read<std::uint16_t>(b);
      case Type::kInt32:
        return read<std::int32_t>(b);
      case Type::kUint32:
        return read<std::uint32_t>(b);
      case Type::kFloat32:
        return read<float>(b);
      case Type::kFloat64:
        return read<double>(b);
    }
    return 0.0;
  }

  void check_list(const Property& p, std::uint64_t n) const {
    if (n * size_of(p.type) > remaining())
      fail(fmt::format("its list '{}' counts {} entries of {} bytes, but only {} bytes are left in the file",
                       p.name, n, size_of(p.type), remaining()));
  }

  void end() {}

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError({file_, 0, 0}, {},
                     fmt::format("{} {} of {} (at byte {}): {}", element_->name, index_ + 1, element_->count,
                                 value_pos_, what));
  }

 private:
  template <class T>
  static double read(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  }

  const std::string& file_;
  std::string_view data_;
  std::size_t pos_, value_pos_ = 0;
  bool swap_;
  const Element* element_ = nullptr;
  std::uint64_t index_ = 0;
};

const Element* find_element(const Header& h, std::string_view name) {
  for (const Element& e : h.elements)
    if (e.name == name) return &e;
  return nullptr;
}

// The index of the property of `e` named `name` (any of `names`), or -1.
int find_property(const Element& e, std::initializer_list<std::string_view> names) {
  for (std::size_t k = 0; k < e.properties.size(); ++k)
    for (std::string_view n : names)
      if (e.properties[k].name == n) return static_cast<int>(k);
  return -1;
}

template <class Data>
PlyMesh read_body(const std::string& file, const Header& h, Data& data, double scale) {
  const auto header_fail = [&](const Element& e, const std::string& what) {
    throw InputError({file, e.line, 1}, {}, what);
  };
  const Element* vertex = find_element(h, "vertex");
  const Element* face = find_element(h, "face");
  int xyz[3] = {-1, -1, -1};
  if (vertex) {
    for (int a = 0; a < 3; ++a) {
      const char* axis = a == 0 ? "x" : a == 1 ? "y" : "z";
      xyz[a] = find_property(*vertex, {axis});
      if (xyz[a] < 0 || vertex->properties[xyz[a]].count_type)
        header_fail(*vertex,
                    fmt::format("the PLY vertex element has no property {} (a single number)", axis));
    }
    if (vertex->count > static_cast<std::uint64_t>(std::numeric_limits<int>::max()))
      header_fail(*vertex, fmt::format("{} vertices: more than {} cannot be read", vertex->count,
                                       std::numeric_limits<int>::max()));
  }
  const int indices = face ? find_property(*face, {"vertex_indices", "vertex_index"}) : -1;
  if (face && (indices < 0 || !face->properties[indices].count_type))
    header_fail(*face, "the PLY face element has no list property vertex_indices (or vertex_index)");
  if (const Element* strips = find_element(h, "tristrips"); strips && strips->count > 0)
    header_fail(*strips, "PLY triangle strips (element tristrips) are not read; save the mesh with faces");
  const double vertices = vertex ? static_cast<double>(vertex->count) : 0.0;

  PlyMesh out;
  std::vector<int> corners;         // of all faces, one after another
  std::vector<std::size_t> starts;  // per face of three or more corners, its first in `corners`
  for (const Element& e : h.elements) {
    if (e.properties.empty() || e.count == 0) continue;
    const std::uint64_t least = Data::least_bytes(e);
    if (e.count > data.remaining() / least)
      header_fail(
          e, fmt::format("the header counts {} '{}' elements of at least {} bytes each, more than the {} "
                         "bytes left in the file hold",
                         e.count, e.name, least, data.remaining()));
    const bool is_vertex = &e == vertex, is_face = &e == face;
    if (is_vertex) out.mesh.vertices.reserve(e.count);
    for (std::uint64_t i = 0; i < e.count; ++i) {
      data.begin(e, i);
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& prop = e.properties[k];
        const double v = data.value(prop, prop.count_type.value_or(prop.type), -1);
        if (!prop.count_type) {
          for (int a = 0; a < 3; ++a)
            if (is_vertex && static_cast<int>(k) == xyz[a]) p[a] = v;
          continue;
        }
        if (!(v >= 0 && v <= 4294967295.0 && v == std::floor(v)))
          data.fail(fmt::format("the list '{}' counts {} entries: not a whole number", prop.name, v));
        const auto n = static_cast<std::uint64_t>(v);
        data.check_list(prop, n);
        const bool face_corners = is_face && static_cast<int>(k) == indices;
        const std::size_t first = corners.size();
        for (std::uint64_t j = 0; j < n; ++j) {
          const double c = data.value(prop, prop.type, static_cast<long long>(j));
          if (!face_corners) continue;
          if (!(c >= 0 && c < vertices && c == std::floor(c)))
            data.fail(fmt::format("a face refers to vertex {}, but the file has {} vertices (counted from 0)",
                                  c, vertex ? vertex->count : 0));
          corners.push_back(static_cast<int>(c));
        }
        if (!face_corners) continue;
        if (n < 3) {
          corners.resize(first);
          ++out.ignored_faces;
        } else {
          starts.push_back(first);
        }
      }
      if (is_vertex) {
        const Eigen::Vector3d placed = p * scale;
        if (!p.allFinite() || !placed.allFinite())
          data.fail(fmt::format("a vertex has a coordinate that is not a finite number: ({}, {}, {})", p.x(),
                                p.y(), p.z()));
        out.mesh.vertices.push_back(placed);
      }
      data.end();
    }
  }

  starts.push_back(corners.size());
  std::vector<Eigen::Vector3d> polygon;
  for (std::size_t f = 0; f + 1 < starts.size(); ++f) {
    const int* c = corners.data() + starts[f];
    const std::size_t n = starts[f + 1] - starts[f];
    if (n == 3) {
      out.mesh.triangles.push_back({c[0], c[1], c[2]});
      continue;
    }
    polygon.clear();
    for (std::size_t j = 0; j < n; ++j) polygon.push_back(out.mesh.vertices[static_cast<std::size_t>(c[j])]);
    for (const auto& t : triangulate_polygon(polygon))
      out.mesh.triangles.push_back({c[t[0]], c[t[1]], c[t[2]]});
  }
  out.mesh.body.assign(out.mesh.triangles.size(), 0);
  if (!out.mesh.triangles.empty()) out.mesh.body_names.emplace_back();
  return out;
}

}  // namespace

PlyMesh read_ply(const std::string& file, std::string_view data, double scale) {
  const Header h = read_header(file, data);
  if (h.format == Format::kAscii) {
    TextData text(file, data, h);
    return read_body(file, h, text, scale);
  }
  BinaryData binary(file, data, h);
  return read_body(file, h, binary, scale);
}

}  // namespace beadtwin::slicer
