#pragma once
//! \file gltf.h
//! \brief glTF 2.0 assets (`.gltf` with external or embedded buffers, `.glb`): reading their
//! triangles, and writing them back with new texture coordinates or positions, nothing else lost.
//!
//! Reading decodes every accessor form the specification allows: byte strides, normalized and
//! integer components (KHR_mesh_quantization), sparse accessors, accessors without a buffer view,
//! and buffer views compressed with EXT_meshopt_compression (decoded with meshoptimizer).
//! KHR_draco_mesh_compression primitives are decoded with Draco. Triangles come from primitives of
//! modes 4, 5 and 6 (strips and fans become triangles; the zero-area triangles that stitch strips
//! are left out); points and lines are counted and skipped. A malformed file is refused with
//! Error(parse_error) and the JSON path of the problem, e.g. "a.glb: meshes[2].primitives[0]
//! .attributes.POSITION: accessor 7 has 12 elements, buffer view 3 holds 9".
//!
//! Writing (write_gltf) starts from the document as read: the primitives given new contents get
//! new accessors, every other part of the file (materials, textures, images, samplers, nodes,
//! skins, animations, cameras, extensions, extras) is kept as it was, accessors and buffer views
//! that nothing uses any more are dropped, and the binary data is written as one buffer (the GLB
//! binary chunk, or `OUT.bin` beside a `.gltf`). Buffer views compressed with
//! EXT_meshopt_compression are written decoded, and rewritten Draco primitives plain.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

namespace detail {
struct GltfContents;
}

//! One triangle primitive's share of a GltfTriangles mesh.
struct GltfPart {
  int mesh = 0;          //!< Index in the document's `meshes`.
  int primitive = 0;     //!< Index in that mesh's `primitives`.
  int node = -1;         //!< The node whose transform placed it (-1: the mesh's own coordinates).
  int first_vertex = 0;  //!< Its vertices are rows first_vertex .. first_vertex+vertex_count-1,
  int vertex_count = 0;  //!< the primitive's own vertices in their order (row i = vertex i).
  int first_face = 0;    //!< Its triangles are rows first_face .. first_face+face_count-1.
  int face_count = 0;
  //! The node's transform mirrors, so the triangles' corners 1 and 2 were swapped to keep them
  //! facing out (glTF 2.0, section 3.5.3).
  bool mirrored = false;
  //! The node's world matrix, which placed the primitive's vertices (identity for node -1).
  Eigen::Matrix4d world = Eigen::Matrix4d::Identity();
  //! For each of its triangles, the position in the primitive's own triangle list (mode 4: the
  //! triangle's index; strips and fans: the triangle the mode makes, counted before stitching
  //! triangles were left out).
  std::vector<int> source_triangle;
};

//! Triangles gathered from a document into one mesh, with where each came from.
struct GltfTriangles {
  Mesh mesh;
  std::vector<GltfPart> parts;
  int skipped_point_primitives = 0;  //!< Primitives of modes 0 (points).
  int skipped_line_primitives = 0;   //!< Primitives of modes 1, 2 and 3 (lines).
};

//! One primitive as `info` describes it.
struct GltfPrimitiveSummary {
  int mode = 4;
  int vertices = 0;
  int triangles = 0;                    //!< Triangles it makes (0 for points and lines).
  std::vector<std::string> attributes;  //!< Attribute names, e.g. POSITION, TEXCOORD_0.
  int morph_targets = 0;
  bool draco = false;                   //!< KHR_draco_mesh_compression.
};

struct GltfMeshSummary {
  std::string name;
  std::vector<GltfPrimitiveSummary> primitives;
  int instances = 0;  //!< Nodes of the default scene that place it.
};

struct GltfSummary {
  std::vector<GltfMeshSummary> meshes;
  std::vector<std::string> extensions_used;
  std::vector<std::string> extensions_required;
  int scenes = 0;
  int default_scene = -1;  //!< -1 when the file has no scene.
  int nodes = 0, materials = 0, textures = 0, images = 0, skins = 0, animations = 0;
};

//! A glTF 2.0 document in memory: its JSON and its decoded binary data. Cheap to copy (shared,
//! immutable).
class GltfDocument {
 public:
  //! Reads `.gltf` or `.glb` (told apart by the file's first bytes, not its name). External
  //! buffers are read from beside the file. Throws Error(parse_error) naming the file and the JSON
  //! path of a problem, Error(io_error) when a file cannot be read, Error(unsupported) for a
  //! required extension harmonia cannot decode (named).
  static GltfDocument read(const std::filesystem::path& path);

  //! The same from bytes in memory; `name` is the file name messages use, `folder` where external
  //! buffers are looked for (empty: external buffers are refused).
  static GltfDocument parse(std::string_view bytes, std::string_view name,
                            const std::filesystem::path& folder);

  //! A document holding `mesh` alone: one scene, one node, one mesh of one primitive with
  //! POSITION (floats) and indices. For writing a mesh of any format as glTF.
  //! `name` is what messages call it (the file the mesh was read from).
  static GltfDocument from_mesh(const Mesh& mesh, const std::string& name = "(mesh)");

  //! The triangles of the default scene in world coordinates: every node that places a mesh
  //! contributes that mesh's triangle primitives, transformed by the node's world matrix (the
  //! winding reversed where that matrix mirrors). A file without a scene gives every mesh once in
  //! its own coordinates.
  [[nodiscard]] GltfTriangles scene_triangles() const;

  //! The triangles of one mesh, in the world coordinates of the first node of the default scene
  //! that places it (its own coordinates when no node does). `primitive` >= 0 keeps only that one.
  [[nodiscard]] GltfTriangles mesh_triangles(int mesh, int primitive = -1) const;

  //! The mesh named `name`, or numbered `name` when no mesh has that name and it is an index.
  //! Throws Error(invalid_input) listing the meshes when there is none.
  [[nodiscard]] int find_mesh(const std::string& name) const;

  [[nodiscard]] int mesh_count() const;
  [[nodiscard]] int primitive_count(int mesh) const;
  //! The texture-coordinate sets (TEXCOORD_n) a primitive has: n = 0 .. count-1.
  [[nodiscard]] int texcoord_sets(int mesh, int primitive) const;
  //! A primitive's TEXCOORD_`set`, one row per vertex, in harmonia's convention (v upwards, as
  //! OBJ: v = 1 - glTF's v); normalized integers decoded. Throws Error(invalid_input) naming the
  //! primitive when it has no such set.
  [[nodiscard]] Eigen::MatrixX2d texcoords(int mesh, int primitive, int set) const;
  [[nodiscard]] GltfSummary summary() const;
  [[nodiscard]] const std::string& name() const;

  [[nodiscard]] const detail::GltfContents& contents() const { return *contents_; }

 private:
  explicit GltfDocument(std::shared_ptr<const detail::GltfContents> contents);
  std::shared_ptr<const detail::GltfContents> contents_;
};

//! New contents for one triangle primitive: its vertices re-made from its own (each new vertex a
//! copy of `source_vertex` with every attribute and morph target delta), its triangles, and new
//! texture coordinates, positions or chart ids where given. The primitive is written as mode 4.
struct GltfPrimitiveUpdate {
  int mesh = 0;
  int primitive = 0;
  std::vector<std::uint32_t> source_vertex;  //!< New vertex -> the primitive's vertex it copies.
  Eigen::Matrix<std::uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor> triangles;  //!< New vertices.
  //! #new vertices by 2, harmonia's convention (v upwards, as OBJ); written flipped to glTF's
  //! (origin at the image's top-left corner). Empty: no new set.
  Eigen::MatrixX2d texcoord;
  //! #new vertices by 3, in the primitive's own coordinates. Empty: positions as they were.
  Eigen::MatrixX3d positions;
  //! One per new vertex, written as the scalar float attribute `_CHART`. Empty: none.
  std::vector<int> chart;
  //! One per new vertex, its atlas page, written as the scalar float attribute `_PAGE` (an atlas
  //! of several pages: TextureAtlas::pages). Empty: none.
  std::vector<int> page;
};

struct GltfWriteOptions {
  //! The TEXCOORD_n set the new texture coordinates go to; -1: the lowest one the primitive lacks
  //! (TEXCOORD_0 on a bare mesh, TEXCOORD_1 on a textured one).
  int texcoord = -1;
  //! Allow `texcoord` to name a set the primitive has (it is replaced).
  bool overwrite = false;
};

//! The TEXCOORD_n set new texture coordinates of a primitive go to under `options`. Throws
//! Error(invalid_input) naming the primitive when the choice names a set it has without
//! `overwrite`, or would leave a gap in its sets.
[[nodiscard]] int texcoord_set_for(const GltfDocument& document, int mesh, int primitive,
                                   const GltfWriteOptions& options);

//! Writes `document` with `updates` applied, as `.glb` or `.gltf` by the extension of `path`
//! (`.gltf` gets its binary data in `path` with `.bin` for extension). Atomic as every writer
//! (harmonia/io.h). Throws Error(invalid_input) before writing anything when an update does not
//! fit its primitive or a texcoord choice breaks glTF's rule that the sets are numbered without
//! gaps, Error(io_error) when a file cannot be written.
void write_gltf(const std::filesystem::path& path, const GltfDocument& document,
                const std::vector<GltfPrimitiveUpdate>& updates,
                const GltfWriteOptions& options = {});

//! Updates that write per-corner texture coordinates into every primitive of `triangles`:
//! `corner_uv` has a row per face of triangles.mesh (u0 v0 u1 v1 u2 v2, harmonia's convention) and
//! `chart_of_face` one entry per face (or none). A primitive's vertex is split wherever its
//! corners' coordinates or charts differ; each new vertex carries its chart id. `page_of_face`
//! (one entry per face, or none) gives each new vertex its atlas page too, and splits vertices
//! where pages differ. Parts without triangles get no update. Each primitive may appear in
//! `triangles` only once.
[[nodiscard]] std::vector<GltfPrimitiveUpdate> texcoord_updates(
    const GltfTriangles& triangles, const Eigen::Matrix<double, Eigen::Dynamic, 6>& corner_uv,
    const std::vector<int>& chart_of_face, const std::vector<int>& page_of_face = {});

//! The texture coordinates TEXCOORD_`set` of every triangle corner of `triangles` (a row per face
//! of triangles.mesh: u0 v0 u1 v1 u2 v2, harmonia's convention), read from each part's primitive.
//! Throws Error(invalid_input) naming the first primitive without that set.
[[nodiscard]] Eigen::Matrix<double, Eigen::Dynamic, 6> corner_texcoords(const GltfDocument& document,
                                                                       const GltfTriangles& triangles, int set);

//! Updates that give every primitive of `triangles` new positions: `positions` has a row per vertex
//! of triangles.mesh, in the coordinates triangles.mesh has (each part's are taken back through
//! its world matrix into the primitive's own). The vertices and their other attributes stay.
//! Each primitive may appear only once (a mesh placed by two nodes would get two shapes).
[[nodiscard]] std::vector<GltfPrimitiveUpdate> position_updates(const GltfTriangles& triangles,
                                                                const Eigen::MatrixX3d& positions);

//! The first primitive that `triangles` holds more than once (a mesh placed by several nodes), as
//! "meshes[M].primitives[P]"; empty when none is.
[[nodiscard]] std::string repeated_primitive(const GltfTriangles& triangles);

//! The triangles of every mesh of the document once (each as GltfDocument::mesh_triangles gives
//! it), one after another: a scene's meshes in one set, an instanced mesh once.
[[nodiscard]] GltfTriangles all_mesh_triangles(const GltfDocument& document);

//! True for `.gltf` and `.glb` (case-insensitive).
[[nodiscard]] bool is_gltf_path(const std::filesystem::path& path);

}  // namespace harmonia
