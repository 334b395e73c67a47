#include "io/obj_layout_lines.h"

#include <charconv>

#include "harmonia/types.h"

namespace harmonia::detail {
namespace {

template <typename Number>
void append(std::string& out, Number value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

// The asset face a written face is.
Eigen::Index asset_face_of(const KeptAsset& kept, Eigen::Index face) {
  return kept.asset_face.size() == 0 ? face : kept.asset_face(face);
}

// The normal at a written corner: the asset face's normal at the corner with the same vertex (a
// repair may have turned the face around or merged its vertices), or -1.
int normal_at(const KeptAsset& kept, Eigen::Index asset_face, int vertex, int corner) {
  const ObjAsset& asset = kept.asset;
  if (asset.normal_faces.rows() == 0) return -1;
  if (asset.mesh.faces(asset_face, corner) == vertex) return asset.normal_faces(asset_face, corner);
  for (int other = 0; other < 3; ++other) {
    if (asset.mesh.faces(asset_face, other) == vertex) return asset.normal_faces(asset_face, other);
  }
  for (int other = 0; other < 3; ++other) {  // A duplicate of the vertex, merged into it.
    if (asset.mesh.vertices.row(asset.mesh.faces(asset_face, other)) == asset.mesh.vertices.row(vertex)) {
      return asset.normal_faces(asset_face, other);
    }
  }
  return -1;
}

}  // namespace

void append_material_libraries(std::string& out, const ObjAsset& asset,
                               const std::filesystem::path& output) {
  std::error_code error;
  const std::filesystem::path to = std::filesystem::weakly_canonical(
      output.parent_path().empty() ? std::filesystem::path(".") : output.parent_path(), error);
  const std::filesystem::path from = std::filesystem::weakly_canonical(asset.folder, error);
  for (const std::string& library : asset.material_libraries) {
    std::string named = library;
    // A relative library name still leads to the library from the output's folder.
    if (!error && from != to && !std::filesystem::path(library).is_absolute()) {
      const std::filesystem::path relative = std::filesystem::relative(from / library, to, error);
      if (!error && !relative.empty()) named = relative.generic_string();
    }
    out += "mtllib " + named + '\n';
  }
}

void append_normals(std::string& out, const ObjAsset& asset) {
  for (Eigen::Index row = 0; row < asset.normals.rows(); ++row) {
    out += "vn";
    for (int axis = 0; axis < 3; ++axis) {
      out += ' ';
      append(out, asset.normals(row, axis));
    }
    out += '\n';
  }
}

void check_kept_asset(const std::filesystem::path& path, Eigen::Index faces, const KeptAsset& kept) {
  const Eigen::Index asset_faces = kept.asset.mesh.faces.rows();
  const auto refuse = [&](const std::string& problem) {
    throw Error(Status::invalid_input, path.string() + ": not written: " + problem);
  };
  if (kept.asset_face.size() == 0) {
    if (faces != asset_faces) {
      refuse(std::to_string(faces) + " faces, but the asset kept has " + std::to_string(asset_faces));
    }
    return;
  }
  if (kept.asset_face.size() != faces) refuse("the asset face map does not have a row per face");
  for (Eigen::Index face = 0; face < faces; ++face) {
    if (kept.asset_face(face) < 0 || kept.asset_face(face) >= asset_faces) {
      refuse("face " + std::to_string(face) + " maps to asset face " +
             std::to_string(kept.asset_face(face)) + " of " + std::to_string(asset_faces));
    }
  }
}

void append_layout_faces(std::string& out, const Eigen::MatrixX3i& faces,
                         const Eigen::MatrixX3i& uv_faces, const KeptAsset* kept,
                         const std::function<std::string(Eigen::Index)>& group_prefix) {
  // The labels in force in the written file so far (-2: none written yet).
  int object = -2, material = -2, smoothing = -2;
  std::string group = "\n";  // No group text can be a newline: the first one is always written.
  for (Eigen::Index face = 0; face < faces.rows(); ++face) {
    const Eigen::Index asset_face = kept != nullptr ? asset_face_of(*kept, face) : -1;
    const auto label = [&](const std::vector<int>& of_face) {
      return kept != nullptr && !of_face.empty() ? of_face[static_cast<std::size_t>(asset_face)] : -1;
    };
    if (kept != nullptr) {
      const std::vector<std::string>& labels = kept->asset.labels;
      if (const int now = label(kept->asset.object_of_face); now != object && now >= 0) {
        out += "o " + labels[static_cast<std::size_t>(now)] + '\n';
        object = now;
      }
    }
    std::string group_now = group_prefix ? group_prefix(face) : std::string();
    if (const int own = label(kept != nullptr ? kept->asset.groups_of_face : std::vector<int>{}); own >= 0) {
      const std::string& names = kept->asset.labels[static_cast<std::size_t>(own)];
      group_now += (group_now.empty() || names.empty() ? "" : " ") + names;
    }
    if (group_now != group && !group_now.empty()) {
      out += "g " + group_now + '\n';
      group = group_now;
    }
    if (kept != nullptr) {
      const std::vector<std::string>& labels = kept->asset.labels;
      if (const int now = label(kept->asset.material_of_face); now != material && now >= 0) {
        out += "usemtl " + labels[static_cast<std::size_t>(now)] + '\n';
        material = now;
      }
      if (const int now = label(kept->asset.smoothing_of_face); now != smoothing && now >= 0) {
        out += "s " + labels[static_cast<std::size_t>(now)] + '\n';
        smoothing = now;
      }
    }
    // Normals on all three corners or none: a face's corners share one form.
    int normals[3] = {-1, -1, -1};
    if (kept != nullptr) {
      for (int corner = 0; corner < 3; ++corner) {
        normals[corner] = normal_at(*kept, asset_face, faces(face, corner), corner);
      }
    }
    const bool with_normals = normals[0] >= 0 && normals[1] >= 0 && normals[2] >= 0;
    out += 'f';
    for (int corner = 0; corner < 3; ++corner) {
      out += ' ';
      append(out, faces(face, corner) + 1);  // OBJ counts from 1.
      out += '/';
      append(out, uv_faces(face, corner) + 1);
      if (with_normals) {
        out += '/';
        append(out, normals[corner] + 1);
      }
    }
    out += '\n';
  }
}

}  // namespace harmonia::detail
