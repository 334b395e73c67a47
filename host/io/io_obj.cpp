// Wavefront OBJ reader: `v` positions and `f` polygons (fan-triangulated), with `vt` texture
// coordinates for read_textured_obj, and for read_obj_asset also `vn` normals, the `vt`/`vn` of
// each corner, `mtllib`, and the `o`, `g`, `usemtl` and `s` in force at each face. Every other
// statement (vp, l, ...) is skipped. Indices may be written `v`, `v/vt`, `v//vn` or `v/vt/vn` (a slot may be left
// empty: `1//`, `2/2/`), and negative indices count back from the latest vertex. A last line
// without a final newline is complete: many exporters write no final newline. The whole file is read into memory and scanned once with
// std::from_chars; a cheap first pass counts the statements so that the arrays are allocated once.

#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "harmonia/io.h"
#include "harmonia/obj_asset.h"
#include "harmonia/types.h"
#include "io/io_support.h"
#include "io/mesh_parsers.h"
#include "io/text_scanner.h"
#include "mesh/mesh_builder.h"

namespace harmonia {
namespace {

using detail::TextScanner;

struct StatementCounts {
  std::size_t vertices = 0;
  std::size_t texture_coordinates = 0;
  std::size_t faces = 0;
};

// Counts lines that start with "v ", "vt " and "f " (an estimate, used only to reserve memory: a
// polygon gives more than one triangle, and continuation lines are not followed).
StatementCounts count_statements(std::string_view text) {
  StatementCounts counts;
  const char* cursor = text.data();
  const char* const end = text.data() + text.size();
  while (end - cursor >= 2) {
    const bool blank_after_1 = cursor[1] == ' ' || cursor[1] == '\t';
    if (cursor[0] == 'v' && blank_after_1) ++counts.vertices;
    if (cursor[0] == 'f' && blank_after_1) ++counts.faces;
    if (cursor[0] == 'v' && cursor[1] == 't') ++counts.texture_coordinates;
    const void* newline = std::memchr(cursor, '\n', static_cast<std::size_t>(end - cursor));
    if (newline == nullptr) break;
    cursor = static_cast<const char*>(newline) + 1;
  }
  return counts;
}

// Statement names are words; anything else on a line's start (control bytes, punctuation) means
// the file is not OBJ text, and saying so beats silently skipping a binary file.
bool is_statement_name(std::string_view word) {
  if (word.empty() || !std::isalpha(static_cast<unsigned char>(word.front()))) return false;
  for (const char c : word) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return true;
}

// What a parse keeps beyond positions and faces.
enum class ObjDetail {
  mesh,      // Positions and faces only.
  textured,  // And the texture coordinates, which every corner must have (read_textured_obj).
  asset,     // And normals, labels and material libraries; corner indices optional (ObjAsset).
};

class ObjParser {
 public:
  ObjParser(std::string_view text, std::string_view file_name, ObjDetail detail)
      : scanner_(text, file_name),
        detail_(detail),
        with_texture_(detail != ObjDetail::mesh) {
    if (text.empty()) scanner_.fail("the file is empty");
    const StatementCounts counts = count_statements(text);
    // Each pre-counted statement exists in the file, so these sizes are bounded by the file size.
    builder_.reserve(counts.vertices, counts.faces);
    if (with_texture_) {
      uv_.reserve(2 * counts.texture_coordinates);
      uv_corners_.reserve(3 * counts.faces);
    }
  }

  void parse() {
    while (scanner_.skip_empty_lines()) {
      const std::string_view statement = scanner_.read_word();
      if (statement == "v") {
        parse_vertex();
      } else if (statement == "f") {
        parse_face();
      } else if (statement == "vt") {
        parse_texture_coordinate();
      } else if (detail_ == ObjDetail::asset && statement == "vn") {
        parse_normal();
      } else if (detail_ == ObjDetail::asset && statement == "mtllib") {
        asset_.material_libraries.emplace_back(scanner_.rest_of_line());
      } else if (detail_ == ObjDetail::asset && statement == "o") {
        object_ = label(scanner_.rest_of_line());
      } else if (detail_ == ObjDetail::asset && statement == "g") {
        groups_ = label(scanner_.rest_of_line());
      } else if (detail_ == ObjDetail::asset && statement == "usemtl") {
        material_ = label(scanner_.rest_of_line());
      } else if (detail_ == ObjDetail::asset && statement == "s") {
        smoothing_ = label(scanner_.rest_of_line());
      } else if (!is_statement_name(statement)) {
        not_a_statement(statement);
      }
      scanner_.next_line();
    }
    if (builder_.triangle_count() == 0) {
      scanner_.fail_at_end("no faces in the file (" + std::to_string(builder_.vertex_count()) +
                           " vertices read)");
    }
    check_forward_references();
  }

  [[nodiscard]] Mesh mesh() const { return builder_.build(); }
  [[nodiscard]] const std::vector<double>& uv() const { return uv_; }
  [[nodiscard]] const std::vector<int>& uv_corners() const { return uv_corners_; }
  // The asset's parts other than the mesh and the texture coordinates (ObjDetail::asset).
  [[nodiscard]] ObjAsset& asset() { return asset_; }
  [[nodiscard]] const std::vector<double>& normals() const { return normals_; }
  [[nodiscard]] const std::vector<int>& normal_corners() const { return normal_corners_; }

 private:
  void parse_vertex() {
    const int vertex = builder_.vertex_count();
    if (vertex == std::numeric_limits<int>::max()) scanner_.fail("too many vertices");
    double position[3];
    for (int axis = 0; axis < 3; ++axis) {
      const auto coordinate = [axis] { return std::string(1, "xyz"[axis]) + " coordinate"; };
      position[axis] = scanner_.read_double(
          [&] { return "the " + coordinate() + " of vertex " + std::to_string(vertex); });
      if (!std::isfinite(position[axis])) {
        scanner_.fail("vertex " + std::to_string(vertex) + " has a non-finite " + coordinate());
      }
    }
    scanner_.skip_numbers([&] { return "a w or colour of vertex " + std::to_string(vertex); });
    builder_.add_vertex(position[0], position[1], position[2]);
  }

  void parse_texture_coordinate() {
    if (!with_texture_) return;  // Only read_textured_obj looks at vt lines.
    const int index = static_cast<int>(uv_.size() / 2);
    const std::string name = "texture coordinate " + std::to_string(index);
    const double u = scanner_.read_double("u of " + name);
    const double v = scanner_.at_line_end() ? 0.0 : scanner_.read_double("v of " + name);
    scanner_.skip_numbers("w of " + name);
    if (!std::isfinite(u) || !std::isfinite(v)) scanner_.fail(name + " is not finite");
    uv_.push_back(u);
    uv_.push_back(v);
  }

  void parse_normal() {
    const int index = static_cast<int>(normals_.size() / 3);
    const std::string name = "normal " + std::to_string(index);
    for (int axis = 0; axis < 3; ++axis) {
      const double value = scanner_.read_double(std::string(1, "xyz"[axis]) + " of " + name);
      if (!std::isfinite(value)) scanner_.fail(name + " is not finite");
      normals_.push_back(value);
    }
  }

  // The index of `text` among the asset's labels (each text kept once).
  int label(std::string_view text) {
    const auto [found, added] = label_index_.try_emplace(std::string(text), 0);
    if (added) {
      found->second = static_cast<int>(asset_.labels.size());
      asset_.labels.emplace_back(text);
    }
    return found->second;
  }

  // One corner: `v`, `v/vt`, `v//vn` or `v/vt/vn`. Exporters also leave the slots they do not
  // fill empty (`1//`, `2/2/`, `3/`), and the common readers (trimesh, Blender, Assimp) take those
  // as the vertex alone: only the vertex index is required.
  void parse_corner(int corner) {
    const std::size_t start = scanner_.offset();
    const auto malformed_corner = [&] {
      scanner_.fail(face_name() + ": malformed corner '" + scanner_.token_at(start) +
                    "' (expected v, v/vt, v//vn or v/vt/vn)");
    };
    std::int64_t vertex = 0, texture = 0, normal = 0;
    if (!scanner_.read_integer_prefix(vertex)) malformed_corner();
    bool has_texture = false, has_normal = false;
    if (scanner_.peek() == '/') {
      scanner_.advance();
      has_texture = scanner_.read_integer_prefix(texture);
      if (scanner_.peek() == '/') {
        scanner_.advance();
        has_normal = scanner_.read_integer_prefix(normal);
      }
    }
    if (!scanner_.at_separator()) malformed_corner();
    corners_.push_back(resolve(vertex, builder_.vertex_count(), corner, "vertex", "vertices"));
    if (detail_ == ObjDetail::asset) {
      // What read_obj takes, an asset reading takes too: a `vt` or `vn` index that leads nowhere
      // is read as none (and one further down the file is resolved once the file is read).
      texture_corners_.push_back(has_texture ? asset_index(texture, static_cast<int>(uv_.size() / 2)) : -1);
      normal_corners_now_.push_back(has_normal ? asset_index(normal, static_cast<int>(normals_.size() / 3))
                                               : -1);
    } else if (with_texture_) {
      if (!has_texture) {
        scanner_.fail(face_name() + ": corner " + std::to_string(corner) +
                      " has no texture index (read_textured_obj needs 'f v/vt ...')");
      }
      texture_corners_.push_back(resolve(texture, static_cast<int>(uv_.size() / 2), corner,
                                         "texture", "texture coordinates"));
    }
  }

  void parse_face() {
    corners_.clear();
    texture_corners_.clear();
    normal_corners_now_.clear();
    while (!scanner_.at_line_end()) parse_corner(static_cast<int>(corners_.size()));
    if (corners_.size() < 3) {
      scanner_.fail(face_name() + " has " + std::to_string(corners_.size()) +
                    " vertices; a face needs at least 3");
    }
    builder_.add_polygon(corners_);
    if (with_texture_) {
      for (std::size_t k = 1; k + 1 < texture_corners_.size(); ++k) {
        uv_corners_.insert(uv_corners_.end(),
                           {texture_corners_[0], texture_corners_[k], texture_corners_[k + 1]});
      }
    }
    if (detail_ == ObjDetail::asset) {
      for (std::size_t k = 1; k + 1 < normal_corners_now_.size(); ++k) {
        normal_corners_.insert(normal_corners_.end(), {normal_corners_now_[0], normal_corners_now_[k],
                                                       normal_corners_now_[k + 1]});
        asset_.object_of_face.push_back(object_);
        asset_.groups_of_face.push_back(groups_);
        asset_.material_of_face.push_back(material_);
        asset_.smoothing_of_face.push_back(smoothing_);
      }
    }
    ++face_count_;
  }

  // An asset's `vt` or `vn` index, 0-based, or -1 where it leads nowhere; an index past the
  // elements read so far is kept and checked against the whole file (drop_dangling_indices).
  static int asset_index(std::int64_t index, int count) {
    if (index > 0) return index - 1 < std::numeric_limits<int>::max() ? static_cast<int>(index - 1) : -1;
    if (index < 0 && count + index >= 0) return static_cast<int>(count + index);
    return -1;
  }

 public:
  // The asset's `vt` and `vn` indices that lead past the file's last one, read as none.
  void drop_dangling_indices() {
    const int texture_coordinates = static_cast<int>(uv_.size() / 2);
    const int normals = static_cast<int>(normals_.size() / 3);
    for (int& index : uv_corners_)
      if (index >= texture_coordinates) index = -1;
    for (int& index : normal_corners_)
      if (index >= normals) index = -1;
  }

 private:
  // OBJ indices are 1-based; negative ones count back from the last element read so far. A
  // positive index may name an element defined further down (trimesh, Blender and Assimp read
  // all elements first): it is checked against the whole file's count once the file is read.
  int resolve(std::int64_t index, int count, int corner, std::string_view kind,
              std::string_view plural) {
    if (index == 0) {
      scanner_.fail(face_name() + ": " + std::string(kind) + " index 0 (corner " +
                    std::to_string(corner) + ") is invalid: OBJ indices start at 1");
    }
    const std::int64_t zero_based = index > 0 ? index - 1 : count + index;
    if (zero_based < 0 || (index < 0 && zero_based >= count)) {
      scanner_.fail(face_name() + ": " + std::string(kind) + " index " + std::to_string(index) +
                    " (corner " + std::to_string(corner) + ") is out of range: " +
                    std::to_string(count) + " " + std::string(plural) + " defined so far");
    }
    if (zero_based >= count) {
      if (zero_based >= std::numeric_limits<int>::max()) {
        scanner_.fail(face_name() + ": " + std::string(kind) + " index " + std::to_string(index) +
                      " (corner " + std::to_string(corner) + ") is out of range");
      }
      forward_references_.push_back({scanner_.line(), face_count_, corner, index, kind});
    }
    return static_cast<int>(zero_based);
  }

  // The indices that named elements further down, against the whole file's counts.
  void check_forward_references() const {
    for (const ForwardReference& reference : forward_references_) {
      const bool vertex = reference.kind == "vertex", texture = reference.kind == "texture";
      const int count = vertex    ? builder_.vertex_count()
                        : texture ? static_cast<int>(uv_.size() / 2)
                                  : static_cast<int>(normals_.size() / 3);
      if (reference.index - 1 < count) continue;
      detail::throw_at_line(scanner_.file_name(), reference.line,
                            "face " + std::to_string(reference.face) + ": " +
                                std::string(reference.kind) + " index " +
                                std::to_string(reference.index) + " (corner " +
                                std::to_string(reference.corner) + ") is out of range: " +
                                std::to_string(count) + " " +
                                (vertex ? "vertices" : texture ? "texture coordinates" : "normals") +
                                " in the file");
    }
  }

  [[noreturn]] void not_a_statement(std::string_view word) const {
    std::string problem = "'";
    problem += detail::printable(word);
    problem += "' is not an OBJ statement (is this a binary file?)";
    scanner_.fail(problem);
  }

  [[nodiscard]] std::string face_name() const { return "face " + std::to_string(face_count_); }

  TextScanner scanner_;
  ObjDetail detail_;
  bool with_texture_;
  detail::MeshBuilder builder_;
  std::vector<double> uv_;       // u0 v0 u1 v1 ... (read_textured_obj only)
  std::vector<int> uv_corners_;  // texture index of each triangle corner (read_textured_obj only)
  std::vector<int> corners_;     // the face being parsed
  std::vector<int> texture_corners_;
  std::vector<int> normal_corners_now_;  // the face being parsed (asset only)
  std::vector<double> normals_;          // x0 y0 z0 x1 ... (asset only)
  std::vector<int> normal_corners_;      // normal index of each triangle corner or -1 (asset only)
  ObjAsset asset_;                       // labels and libraries (asset only)
  std::map<std::string, int, std::less<>> label_index_;
  int object_ = -1, groups_ = -1, material_ = -1, smoothing_ = -1;  // the labels in force
  int face_count_ = 0;
  struct ForwardReference {
    std::int64_t line;
    int face;
    int corner;
    std::int64_t index;     // 1-based, as written
    std::string_view kind;  // "vertex", "texture" or "normal"
  };
  std::vector<ForwardReference> forward_references_;
};

}  // namespace

namespace detail {

Mesh parse_obj(std::string_view contents, std::string_view name) {
  ObjParser parser(contents, name, ObjDetail::mesh);
  parser.parse();
  return parser.mesh();
}

TexturedMesh parse_textured_obj(std::string_view contents, std::string_view name) {
  ObjParser parser(contents, name, ObjDetail::textured);
  parser.parse();
  TexturedMesh textured;
  textured.mesh = parser.mesh();
  textured.uv = matrix_from_rows<Eigen::MatrixX2d>(parser.uv());
  textured.uv_faces = matrix_from_rows<Eigen::MatrixX3i>(parser.uv_corners());
  return textured;
}

ObjAsset parse_obj_asset(std::string_view contents, std::string_view name) {
  ObjParser parser(contents, name, ObjDetail::asset);
  parser.parse();
  parser.drop_dangling_indices();
  ObjAsset asset = std::move(parser.asset());
  asset.mesh = parser.mesh();
  asset.texcoords = matrix_from_rows<Eigen::MatrixX2d>(parser.uv());
  asset.texcoord_faces = matrix_from_rows<Eigen::MatrixX3i>(parser.uv_corners());
  asset.normals = matrix_from_rows<Eigen::MatrixX3d>(parser.normals());
  asset.normal_faces = matrix_from_rows<Eigen::MatrixX3i>(parser.normal_corners());
  return asset;
}

}  // namespace detail

bool ObjAsset::carries_more_than_a_mesh() const {
  const auto any_label = [](const std::vector<int>& of_face) {
    for (const int label : of_face)
      if (label >= 0) return true;
    return false;
  };
  return (texcoord_faces.size() > 0 && texcoord_faces.maxCoeff() >= 0) ||
         (normal_faces.size() > 0 && normal_faces.maxCoeff() >= 0) || !material_libraries.empty() ||
         any_label(object_of_face) || any_label(groups_of_face) || any_label(material_of_face) ||
         any_label(smoothing_of_face);
}

ObjAsset read_obj_asset(const std::filesystem::path& path) {
  ObjAsset asset = detail::parse_obj_asset(detail::read_whole_file(path), path.string());
  asset.folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  return asset;
}

Mesh read_obj(const std::filesystem::path& path) {
  return detail::parse_obj(detail::read_whole_file(path), path.string());
}

TexturedMesh read_textured_obj(const std::filesystem::path& path) {
  return detail::parse_textured_obj(detail::read_whole_file(path), path.string());
}

}  // namespace harmonia
