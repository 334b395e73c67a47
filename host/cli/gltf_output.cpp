#include "cli/gltf_output.h"

#include "cli/common.h"
#include "harmonia/gltf.h"

namespace harmonia::cli {
namespace {

// The document `input` is (or holds) and the triangles the program read from it.
struct ReadAgain {
  GltfDocument document;
  GltfTriangles triangles;
};

ReadAgain read_again(const std::string& input) {
  if (is_gltf_path(input)) {
    GltfDocument document = load_gltf(input);
    GltfTriangles triangles = gltf_triangles_of(document);
    return {std::move(document), std::move(triangles)};
  }
  GltfDocument document = GltfDocument::from_mesh(load_mesh(input), input);
  GltfTriangles triangles = document.scene_triangles();
  return {std::move(document), std::move(triangles)};
}

void write(const std::string& output, const ReadAgain& read,
           const std::vector<GltfPrimitiveUpdate>& updates, const GltfWriteOptions& options = {}) {
  write_output([&] { write_gltf(output, read.document, updates, options); });
}

std::vector<GltfPrimitiveUpdate> usage_checked(auto&& make) {
  try {
    return make();
  } catch (const Error& error) {
    throw CliFailure(ExitCode::usage, error.what());
  }
}

}  // namespace

void add_texcoord_options(CLI::App& command, GltfWriteOptions& options) {
  command
      .add_option("--texcoord", options.texcoord,
                  "glTF output: the TEXCOORD_n set the map goes to (default: the lowest set each "
                  "primitive lacks: TEXCOORD_0 on a bare mesh, TEXCOORD_1 on a textured one)")
      ->check(CLI::Range(0, 31));
  command.add_flag("--overwrite", options.overwrite,
                   "glTF output: allow --texcoord to name a set the primitive has (replaced)");
}

void write_layout_gltf(const std::string& input, const std::string& output,
                       const TexturedMesh& layout, const GltfWriteOptions& options) {
  const ReadAgain read = read_again(input);
  for (const GltfPart& part : read.triangles.parts) {
    try {
      (void)texcoord_set_for(read.document, part.mesh, part.primitive, options);
    } catch (const Error& error) {
      throw CliFailure(ExitCode::usage, error.what());
    }
  }
  if (layout.mesh.faces.rows() != read.triangles.mesh.faces.rows() ||
      layout.mesh.faces != read.triangles.mesh.faces) {
    throw CliFailure(ExitCode::usage, output + ": the map's faces are not the file's (a repair "
                                      "changed them); glTF output keeps the file's own faces");
  }
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv(layout.mesh.faces.rows(), 6);
  for (Eigen::Index face = 0; face < layout.uv_faces.rows(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      corner_uv.block<1, 2>(face, 2 * corner) = layout.uv.row(layout.uv_faces(face, corner));
    }
  }
  write(output, read, usage_checked([&] { return texcoord_updates(read.triangles, corner_uv, {}); }),
        options);
}

void write_positions_gltf(const std::string& input, const std::string& output,
                          const Eigen::MatrixX3d& positions) {
  const ReadAgain read = read_again(input);
  write(output, read, usage_checked([&] { return position_updates(read.triangles, positions); }));
}

}  // namespace harmonia::cli
