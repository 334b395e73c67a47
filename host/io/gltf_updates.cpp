// From a per-corner layout of a GltfTriangles mesh to updates of its primitives: each primitive's
// vertices split where the layout gives one vertex two coordinates (harmonia/gltf.h).

#include <Eigen/LU>
#include <map>
#include <string>
#include <tuple>

#include "harmonia/gltf.h"
#include "harmonia/types.h"

namespace harmonia {

std::string repeated_primitive(const GltfTriangles& triangles) {
  std::map<std::pair<int, int>, int> seen;
  for (const GltfPart& part : triangles.parts) {
    if (++seen[{part.mesh, part.primitive}] == 2) {
      return "meshes[" + std::to_string(part.mesh) + "].primitives[" + std::to_string(part.primitive) + "]";
    }
  }
  return {};
}

std::vector<GltfPrimitiveUpdate> texcoord_updates(
    const GltfTriangles& triangles, const Eigen::Matrix<double, Eigen::Dynamic, 6>& corner_uv,
    const std::vector<int>& chart_of_face, const std::vector<int>& page_of_face) {
  if (corner_uv.rows() != triangles.mesh.faces.rows() ||
      (!chart_of_face.empty() && chart_of_face.size() != static_cast<std::size_t>(corner_uv.rows())) ||
      (!page_of_face.empty() && page_of_face.size() != static_cast<std::size_t>(corner_uv.rows()))) {
    throw Error(Status::invalid_input, "texcoord_updates: the layout has " +
                                           std::to_string(corner_uv.rows()) + " faces, the mesh " +
                                           std::to_string(triangles.mesh.faces.rows()));
  }
  if (const std::string repeated = repeated_primitive(triangles); !repeated.empty()) {
    throw Error(Status::invalid_input, repeated + " is placed by several nodes: each would give its "
                                       "vertices other values (pick one mesh, e.g. --mesh)");
  }
  std::vector<GltfPrimitiveUpdate> updates;
  for (const GltfPart& part : triangles.parts) {
    if (part.face_count == 0) continue;
    GltfPrimitiveUpdate update;
    update.mesh = part.mesh;
    update.primitive = part.primitive;
    // One new vertex per distinct (vertex, u, v, chart, page) among the part's corners, in order
    // of first use.
    std::map<std::tuple<int, double, double, int, int>, std::uint32_t> new_vertex_of;
    std::vector<double> us, vs;
    update.triangles.resize(part.face_count, 3);
    for (int local = 0; local < part.face_count; ++local) {
      const int face = part.first_face + local;
      const int chart = chart_of_face.empty() ? 0 : chart_of_face[static_cast<std::size_t>(face)];
      const int page = page_of_face.empty() ? 0 : page_of_face[static_cast<std::size_t>(face)];
      for (int corner = 0; corner < 3; ++corner) {
        const int vertex = triangles.mesh.faces(face, corner) - part.first_vertex;
        const double u = corner_uv(face, 2 * corner), v = corner_uv(face, 2 * corner + 1);
        const auto [found, added] = new_vertex_of.try_emplace(
            {vertex, u, v, chart, page}, static_cast<std::uint32_t>(update.source_vertex.size()));
        if (added) {
          update.source_vertex.push_back(static_cast<std::uint32_t>(vertex));
          us.push_back(u);
          vs.push_back(v);
          if (!chart_of_face.empty()) update.chart.push_back(chart);
          if (!page_of_face.empty()) update.page.push_back(page);
        }
        // Undo the swap that kept a mirrored instance's triangles facing out: the primitive's
        // own winding is written.
        const int written_corner = part.mirrored && corner > 0 ? 3 - corner : corner;
        update.triangles(local, written_corner) = found->second;
      }
    }
    update.texcoord.resize(static_cast<Eigen::Index>(us.size()), 2);
    for (std::size_t i = 0; i < us.size(); ++i) {
      update.texcoord(static_cast<Eigen::Index>(i), 0) = us[i];
      update.texcoord(static_cast<Eigen::Index>(i), 1) = vs[i];
    }
    updates.push_back(std::move(update));
  }
  return updates;
}

std::vector<GltfPrimitiveUpdate> position_updates(const GltfTriangles& triangles,
                                                  const Eigen::MatrixX3d& positions) {
  if (positions.rows() != triangles.mesh.vertices.rows()) {
    throw Error(Status::invalid_input, "position_updates: " + std::to_string(positions.rows()) +
                                           " positions for " +
                                           std::to_string(triangles.mesh.vertices.rows()) + " vertices");
  }
  if (const std::string repeated = repeated_primitive(triangles); !repeated.empty()) {
    throw Error(Status::invalid_input, repeated + " is placed by several nodes: each would give its "
                                       "vertices other values (pick one mesh, e.g. --mesh)");
  }
  std::vector<GltfPrimitiveUpdate> updates;
  for (const GltfPart& part : triangles.parts) {
    if (part.face_count == 0) continue;
    GltfPrimitiveUpdate update;
    update.mesh = part.mesh;
    update.primitive = part.primitive;
    update.source_vertex.resize(static_cast<std::size_t>(part.vertex_count));
    for (int v = 0; v < part.vertex_count; ++v) update.source_vertex[static_cast<std::size_t>(v)] = static_cast<std::uint32_t>(v);
    update.triangles.resize(part.face_count, 3);
    for (int local = 0; local < part.face_count; ++local) {
      for (int corner = 0; corner < 3; ++corner) {
        const int written_corner = part.mirrored && corner > 0 ? 3 - corner : corner;
        update.triangles(local, written_corner) = static_cast<std::uint32_t>(
            triangles.mesh.faces(part.first_face + local, corner) - part.first_vertex);
      }
    }
    const Eigen::Matrix4d to_local = part.world.inverse();
    update.positions.resize(part.vertex_count, 3);
    for (int v = 0; v < part.vertex_count; ++v) {
      const Eigen::Vector4d world(positions(part.first_vertex + v, 0), positions(part.first_vertex + v, 1),
                                  positions(part.first_vertex + v, 2), 1.0);
      update.positions.row(v) = (to_local * world).head<3>().transpose();
    }
    updates.push_back(std::move(update));
  }
  return updates;
}

GltfTriangles all_mesh_triangles(const GltfDocument& document) {
  GltfTriangles all;
  std::vector<Eigen::MatrixX3d> vertex_blocks;
  std::vector<Eigen::MatrixX3i> face_blocks;
  int vertices = 0, faces = 0;
  for (int mesh = 0; mesh < document.mesh_count(); ++mesh) {
    GltfTriangles one = document.mesh_triangles(mesh);
    for (GltfPart& part : one.parts) {
      part.first_vertex += vertices;
      part.first_face += faces;
      all.parts.push_back(std::move(part));
    }
    one.mesh.faces.array() += vertices;
    vertices += one.mesh.vertex_count();
    faces += one.mesh.face_count();
    vertex_blocks.push_back(std::move(one.mesh.vertices));
    face_blocks.push_back(std::move(one.mesh.faces));
    all.skipped_point_primitives += one.skipped_point_primitives;
    all.skipped_line_primitives += one.skipped_line_primitives;
  }
  all.mesh.vertices.resize(vertices, 3);
  all.mesh.faces.resize(faces, 3);
  int vertex_row = 0, face_row = 0;
  for (std::size_t block = 0; block < vertex_blocks.size(); ++block) {
    all.mesh.vertices.middleRows(vertex_row, vertex_blocks[block].rows()) = vertex_blocks[block];
    all.mesh.faces.middleRows(face_row, face_blocks[block].rows()) = face_blocks[block];
    vertex_row += static_cast<int>(vertex_blocks[block].rows());
    face_row += static_cast<int>(face_blocks[block].rows());
  }
  return all;
}

}  // namespace harmonia
