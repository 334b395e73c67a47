// Edit files (harmonia/edit_file.h): JSON, validated field by field so that every error names the
// field it is about.

#include "harmonia/edit_file.h"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

namespace harmonia {
namespace {

using nlohmann::json;

class EditParser {
 public:
  EditParser(const Mesh& mesh, std::string source) : mesh_(mesh), source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
    throw Error(Status::invalid_input, source_ + ": " + field + ": " + problem);
  }

  const json& member(const json& object, const std::string& field, const std::string& key) const {
    const auto found = object.find(key);
    if (found == object.end()) fail(field, "missing");
    return *found;
  }

  double number(const json& value, const std::string& field) const {
    if (!value.is_number()) fail(field, "expected a number, got " + std::string(value.type_name()));
    const double number = value.get<double>();
    if (!std::isfinite(number)) fail(field, "not finite");
    return number;
  }

  Eigen::Vector3d vector3(const json& value, const std::string& field) const {
    if (!value.is_array() || value.size() != 3) fail(field, "expected an array of 3 numbers");
    Eigen::Vector3d result;
    for (int k = 0; k < 3; ++k) result[k] = number(value[static_cast<std::size_t>(k)], field + "[" + std::to_string(k) + "]");
    return result;
  }

  // A vertex set: {"vertices": [...]} or {"sphere": {"center": [...], "radius": r}}.
  std::vector<int> vertex_set(const json& set, const std::string& field) const {
    if (!set.is_object()) fail(field, "expected an object with \"vertices\" or \"sphere\"");
    const bool has_list = set.contains("vertices"), has_ball = set.contains("sphere");
    if (has_list && has_ball) fail(field, "give either \"vertices\" or \"sphere\", not both");
    if (!has_list && !has_ball) fail(field, "expected \"vertices\" or \"sphere\"");
    std::vector<int> vertices;
    if (has_list) {
      const json& list = set["vertices"];
      const std::string list_field = field + ".vertices";
      if (!list.is_array()) fail(list_field, "expected an array of vertex indices");
      for (std::size_t k = 0; k < list.size(); ++k) {
        const json& index = list[k];
        const std::string index_field = list_field + "[" + std::to_string(k) + "]";
        if (!index.is_number_integer()) fail(index_field, "expected an integer vertex index");
        const long long v = index.get<long long>();
        if (v < 0 || v >= mesh_.vertex_count())
          fail(index_field, "vertex index " + std::to_string(v) + " is outside the mesh's " +
                                std::to_string(mesh_.vertex_count()) + " vertices");
        vertices.push_back(static_cast<int>(v));
      }
      return vertices;
    }
    const json& ball = set["sphere"];
    const std::string ball_field = field + ".sphere";
    if (!ball.is_object()) fail(ball_field, "expected {\"center\": [x, y, z], \"radius\": r}");
    const Eigen::Vector3d center = vector3(member(ball, ball_field + ".center", "center"), ball_field + ".center");
    const double radius = number(member(ball, ball_field + ".radius", "radius"), ball_field + ".radius");
    if (!(radius > 0.0)) fail(ball_field + ".radius", "must be positive");
    for (int v = 0; v < mesh_.vertex_count(); ++v)
      if ((mesh_.vertices.row(v).transpose() - center).norm() <= radius) vertices.push_back(v);
    if (vertices.empty()) fail(ball_field, "selects no vertex of the mesh");
    return vertices;
  }

  SimilarityTransform transform(const json& handle, const std::vector<int>& vertices,
                                const std::string& field) const {
    SimilarityTransform result;
    result.center = Eigen::Vector3d::Zero();
    for (const int v : vertices) result.center += mesh_.vertices.row(v).transpose();
    result.center /= static_cast<double>(vertices.size());
    if (const auto found = handle.find("translate"); found != handle.end())
      result.translation = vector3(*found, field + ".translate");
    if (const auto found = handle.find("scale"); found != handle.end()) {
      result.scale = number(*found, field + ".scale");
      if (!(result.scale > 0.0)) fail(field + ".scale", "must be positive");
    }
    if (const auto found = handle.find("rotate"); found != handle.end()) {
      const std::string rotate_field = field + ".rotate";
      if (!found->is_object()) fail(rotate_field, "expected {\"axis\", \"degrees\", \"center\"}");
      const Eigen::Vector3d axis = vector3(member(*found, rotate_field + ".axis", "axis"), rotate_field + ".axis");
      if (axis.norm() == 0.0) fail(rotate_field + ".axis", "must not be zero");
      const double degrees = number(member(*found, rotate_field + ".degrees", "degrees"), rotate_field + ".degrees");
      result.rotation = Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized());
      if (const auto center = found->find("center"); center != found->end())
        result.center = vector3(*center, rotate_field + ".center");
    }
    return result;
  }

  EditDescription parse(const std::string& text) const {
    json document;
    try {
      document = json::parse(text);
    } catch (const json::parse_error& error) {
      // Line and column of the byte where parsing failed.
      const std::size_t byte = std::min<std::size_t>(error.byte > 0 ? error.byte - 1 : 0, text.size());
      std::size_t line = 1, column = 1;
      for (std::size_t i = 0; i < byte; ++i) {
        if (text[i] == '\n') {
          ++line;
          column = 1;
        } else {
          ++column;
        }
      }
      throw Error(Status::parse_error, source_ + ":" + std::to_string(line) + ":" +
                                           std::to_string(column) + ": not valid JSON (" +
                                           error.what() + ")");
    }
    if (!document.is_object()) fail("(top level)", "expected a JSON object");
    EditDescription edit;
    if (const auto found = document.find("mesh"); found != document.end() && found->is_string())
      edit.mesh_name = found->get<std::string>();
    if (const auto found = document.find("description"); found != document.end() && found->is_string())
      edit.description = found->get<std::string>();
    if (const auto found = document.find("fixed"); found != document.end())
      edit.regions.fixed = vertex_set(*found, "fixed");
    if (const auto found = document.find("region_of_interest"); found != document.end())
      edit.regions.region_of_interest = vertex_set(*found, "region_of_interest");
    const json& handles = member(document, "handles", "handles");
    if (!handles.is_array() || handles.empty()) fail("handles", "expected a non-empty array of handles");
    for (std::size_t i = 0; i < handles.size(); ++i) {
      const std::string field = "handles[" + std::to_string(i) + "]";
      std::vector<int> vertices = vertex_set(handles[i], field);
      if (vertices.empty()) fail(field + ".vertices", "empty: a handle needs at least one vertex");
      edit.transforms.push_back(transform(handles[i], vertices, field));
      edit.regions.handles.push_back(std::move(vertices));
    }
    return edit;
  }

 private:
  const Mesh& mesh_;
  std::string source_;
};

}  // namespace

EditDescription parse_edit(const std::string& json_text, const Mesh& mesh, const std::string& source) {
  return EditParser(mesh, source).parse(json_text);
}

EditDescription read_edit_file(const std::filesystem::path& path, const Mesh& mesh) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(Status::io_error, "cannot read edit file " + path.string());
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw Error(Status::io_error, "error reading edit file " + path.string());
  return parse_edit(text.str(), mesh, path.string());
}

}  // namespace harmonia
