// The texture atlas writer (harmonia/atlas_io.h): the file is formatted in memory, numbers with
// std::to_chars (the shortest form that reads back to the same double, as io_write.cpp), and
// written atomically (io/atomic_file.h). The UV indexing is the atlas metrics' own
// (atlas/atlas_metrics.h), so the boundary edges atlaseval.py finds in the file are the ones the
// library measured.

#include <charconv>
#include <string>
#include <string_view>

#include "atlas/atlas_metrics.h"
#include "harmonia/atlas_io.h"
#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "io/obj_layout_lines.h"

namespace harmonia {
namespace {

[[noreturn]] void refuse(const std::filesystem::path& path, const std::string& problem) {
  throw Error(Status::invalid_input, path.string() + ": atlas not written: " + problem);
}

template <typename Number>
void append(std::string& out, Number value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

// "v x y z" or "vt u v" for every row of `values`.
void append_rows(std::string& out, std::string_view keyword,
                 const Eigen::Ref<const Eigen::MatrixXd>& values) {
  for (Eigen::Index row = 0; row < values.rows(); ++row) {
    out += keyword;
    for (Eigen::Index column = 0; column < values.cols(); ++column) {
      out += ' ';
      append(out, values(row, column));
    }
    out += '\n';
  }
}

// The first row of `values` with a value that is not finite, or -1.
Eigen::Index first_row_not_finite(const Eigen::Ref<const Eigen::MatrixXd>& values) {
  for (Eigen::Index row = 0; row < values.rows(); ++row) {
    if (!values.row(row).allFinite()) return row;
  }
  return -1;
}

}  // namespace

namespace {

void write_atlas(const std::filesystem::path& obj, const Mesh& mesh, const TextureAtlas& atlas,
                 const detail::KeptAsset* kept) {
  if (const std::string problem = detail::atlas_mismatch(mesh, atlas); !problem.empty()) {
    refuse(obj, problem);
  }
  if (const Eigen::Index vertex = first_row_not_finite(mesh.vertices); vertex >= 0) {
    refuse(obj, "vertex " + std::to_string(vertex) + " is not finite");
  }
  if (const Eigen::Index face = first_row_not_finite(atlas.corner_uv); face >= 0) {
    refuse(obj, "the UVs of face " + std::to_string(face) + " are not finite");
  }
  if (kept != nullptr) detail::check_kept_asset(obj, mesh.faces.rows(), *kept);
  const detail::AtlasUvLayout layout = detail::atlas_uv_layout(mesh, atlas);

  std::string out = "# harmonia texture atlas\n# ";
  append(out, atlas.charts.size());
  out += " charts, ";
  append(out, atlas.resolution);
  out += " x ";
  append(out, atlas.height_texels());
  out += " texels";
  if (atlas.pages > 1) {
    out += " a page, ";
    append(out, atlas.pages);
    out += " pages (a chart's group chart_N_aP names its page P)";
  }
  out += "\n# the atlas size in texels (width height atlases), as atlaseval.py reads it:\n";
  out += "# xatlas_atlas ";
  append(out, atlas.resolution);
  out += ' ';
  append(out, atlas.height_texels());
  out += ' ';
  append(out, atlas.pages);
  out += '\n';
  if (kept != nullptr) detail::append_material_libraries(out, kept->asset, obj);
  append_rows(out, "v", mesh.vertices);
  append_rows(out, "vt", layout.uv);
  if (kept != nullptr) detail::append_normals(out, kept->asset);
  detail::append_layout_faces(out, mesh.faces, layout.uv_faces, kept, [&](Eigen::Index face) {
    const int chart = atlas.chart_of_face[static_cast<std::size_t>(face)];
    std::string group = "chart_" + std::to_string(chart);
    if (atlas.pages > 1 && chart >= 0)
      group += "_a" + std::to_string(atlas.charts[static_cast<std::size_t>(chart)].page);
    return group;
  });
  detail::write_file_atomically(obj, out);
}

}  // namespace

void write_atlas_obj(const std::filesystem::path& obj, const Mesh& mesh,
                     const TextureAtlas& atlas) {
  write_atlas(obj, mesh, atlas, nullptr);
}

void write_atlas_obj(const std::filesystem::path& obj, const Mesh& mesh, const TextureAtlas& atlas,
                     const ObjAsset& asset, const Eigen::VectorXi& asset_face) {
  const detail::KeptAsset kept{asset, asset_face};
  write_atlas(obj, mesh, atlas, &kept);
}

}  // namespace harmonia
