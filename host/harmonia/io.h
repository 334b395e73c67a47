#pragma once
//! \file io.h
//! \brief Reading and writing meshes: OBJ, OFF, PLY (ASCII and binary), STL (ASCII and binary);
//! reading glTF 2.0 (`.gltf`, `.glb`: the default scene's triangles in world coordinates; see
//! harmonia/gltf.h for the document itself and for writing glTF).
//!
//! Readers validate as they go and throw harmonia::Error with Status::parse_error and a message of the
//! form "FILE:LINE: problem" (or "FILE: byte OFFSET: problem" for binary files), or Status::io_error
//! when the file cannot be opened or its extension is unknown. Polygons are triangulated as fans;
//! OBJ `v/vt/vn` forms and negative (relative) indices are accepted; `vt`/`vn` data is ignored. NaN or
//! infinite coordinates, indices out of range, truncated files, absurd element counts and binary
//! garbage are errors, never crashes. Messages number vertices and faces from 0 in file order and
//! quote indices as written in the file. OBJ faces may only use vertices defined above them (as the
//! format specifies). STL corners at exactly the same position become one vertex, numbered in order
//! of first appearance. A text file whose last face line ends inside a number, with no final
//! newline, is reported as truncated: cut short there ("f 1 2 34" to "f 1 2 3") it would still
//! read as a valid but wrong face.
//!
//! Writers print coordinates in the shortest form that reads back to the same double (PLY stores
//! doubles), so write-then-read gives identical arrays. They write to a temporary file beside the
//! target and rename it into place, so an existing file is never left half-written. A mesh with a
//! non-finite value or an index out of range is refused with Error(invalid_input) before anything is
//! written; a target that cannot be written gives Error(io_error).

#include <filesystem>

#include "harmonia/mesh.h"
#include "harmonia/obj_asset.h"

namespace harmonia {

enum class MeshFormat { obj, off, ply, stl, gltf };

//! Format from the file name's extension (case-insensitive). Throws Error(io_error) if unknown.
[[nodiscard]] MeshFormat format_from_extension(const std::filesystem::path& path);

//! Reads any supported format (chosen by extension). A glTF file gives
//! GltfDocument::read(path).scene_triangles().mesh.
[[nodiscard]] Mesh read_mesh(const std::filesystem::path& path);
[[nodiscard]] Mesh read_obj(const std::filesystem::path& path);
[[nodiscard]] Mesh read_off(const std::filesystem::path& path);
[[nodiscard]] Mesh read_ply(const std::filesystem::path& path);
[[nodiscard]] Mesh read_stl(const std::filesystem::path& path);

//! Every writer (meshes and pictures) replaces its file atomically: the new contents are written
//! beside it and renamed over it only when complete, so a failure or a killed process leaves the
//! old file as it was and no temporary file behind. A symbolic link is written through (the file
//! it leads to is replaced), an existing file keeps its permission bits, and a device such as
//! /dev/null is written as it is. Failures throw Error(io_error) naming the file.
//!
//! Throws Error(io_error) naming the file unless a writer could create `path` now (its folder
//! exists and may be written to, and `path` is no folder): a program calls it for its outputs
//! before it starts the work.
void check_writable(const std::filesystem::path& path);

//! For a program's own SIGINT/SIGTERM handler (the library installs none: signal handlers are
//! the process's): removes the new files that writers are writing at this moment where they had
//! to be named beside their targets (file systems without unnamed files, or no /proc), so that an
//! interrupted run leaves nothing behind; the targets are untouched. Async-signal-safe: it only
//! reads fixed memory and calls unlink.
void remove_unfinished_outputs() noexcept;

//! Installs SIGINT and SIGTERM handlers that call remove_unfinished_outputs and then let the signal
//! end the process as it would have (its exit status still names the signal). For programs
//! without signal handling of their own: it changes process-wide state, so harmonia never calls it
//! by itself. The harmonia program does.
void remove_unfinished_outputs_on_signals();

//! Writes OBJ, OFF or PLY (binary little-endian) chosen by extension. STL output is not offered.
void write_mesh(const std::filesystem::path& path, const Mesh& mesh);

//! Writes an OBJ with `v` lines (mesh.vertices in order), `vt` lines (uv) and faces `f a/ta b/tb c/tc`.
void write_obj(const std::filesystem::path& path, const TexturedMesh& textured);

//! The same, keeping what an OBJ asset carried (harmonia/obj_asset.h): its material libraries
//! (named from OUT's folder), normals, and the `o`, `g`, `usemtl` and `s` of each face; the new
//! `vt` replace the asset's own (OBJ holds one set). `asset_face` gives each face of `textured`
//! the asset's face it is (a repair may drop or renumber faces); empty: the same faces.
void write_obj(const std::filesystem::path& path, const TexturedMesh& textured,
               const ObjAsset& asset, const Eigen::VectorXi& asset_face = {});

//! Writes an OBJ with one `vt` per vertex: faces `f a/a b/b c/c`. uv is #V by 2.
void write_obj(const std::filesystem::path& path, const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! Reads an OBJ's `vt` lines and the texture indices of its faces (for `harmonia eval MESH PARAM`).
//! Throws Error(parse_error) if a face lacks texture indices.
[[nodiscard]] TexturedMesh read_textured_obj(const std::filesystem::path& path);

}  // namespace harmonia
