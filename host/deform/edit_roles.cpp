#include "deform/edit_roles.h"

#include <numeric>

namespace harmonia::detail {
namespace {

// Union-find over the vertices, with path halving.
int representative(std::vector<int>& parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

// Marks `vertices` with `role`; returns what is wrong with the set, if anything.
std::string mark(const std::vector<int>& vertices, int role, const std::string& set_name,
                 const std::vector<std::string>& role_names, std::vector<int>& roles) {
  const auto vertex_count = static_cast<int>(roles.size());
  for (const int v : vertices) {
    if (v < 0 || v >= vertex_count)
      return set_name + ": vertex index " + std::to_string(v) + " is outside the mesh's " +
             std::to_string(vertex_count) + " vertices";
    if (roles[v] != EditRoles::kFree && roles[v] != role)
      return "vertex " + std::to_string(v) + " is in both " +
             role_names[static_cast<std::size_t>(roles[v] + 2)] + " and " + set_name;
    roles[v] = role;
  }
  return {};
}

}  // namespace

std::string resolve_edit_roles(const Mesh& mesh, const EditRegions& regions, EditRoles& roles) {
  const int vertex_count = mesh.vertex_count();
  roles = EditRoles{};
  roles.handle_count = static_cast<int>(regions.handles.size());
  roles.role.assign(static_cast<std::size_t>(vertex_count), EditRoles::kFree);
  if (regions.handles.empty()) return "no handle: an edit needs at least one";
  // role_names[role + 2]: the set's name for messages.
  std::vector<std::string> role_names = {"fixed", "free"};
  for (int i = 0; i < roles.handle_count; ++i) role_names.push_back("handle " + std::to_string(i));
  if (std::string problem = mark(regions.fixed, EditRoles::kFixed, "fixed", role_names, roles.role);
      !problem.empty())
    return problem;
  for (int i = 0; i < roles.handle_count; ++i) {
    const std::vector<int>& handle = regions.handles[static_cast<std::size_t>(i)];
    const std::string name = "handle " + std::to_string(i);
    if (handle.empty()) return name + " has no vertex";
    if (std::string problem = mark(handle, i, name, role_names, roles.role); !problem.empty())
      return problem;
  }
  if (!regions.region_of_interest.empty()) {
    std::vector<bool> inside(static_cast<std::size_t>(vertex_count), false);
    for (const int v : regions.region_of_interest) {
      if (v < 0 || v >= vertex_count)
        return "region of interest: vertex index " + std::to_string(v) + " is outside the mesh's " +
               std::to_string(vertex_count) + " vertices";
      inside[static_cast<std::size_t>(v)] = true;
    }
    for (int v = 0; v < vertex_count; ++v)
      if (!inside[static_cast<std::size_t>(v)] && roles.role[v] == EditRoles::kFree)
        roles.role[v] = EditRoles::kFixed;
  }
  // A vertex that no face uses cannot be placed by the Poisson equation: it stays where it is.
  std::vector<bool> used(static_cast<std::size_t>(vertex_count), false);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(mesh.faces(f, k))] = true;
  for (int v = 0; v < vertex_count; ++v)
    if (!used[static_cast<std::size_t>(v)] && roles.role[v] == EditRoles::kFree)
      roles.role[v] = EditRoles::kFixed;
  // Every connected part with a free vertex needs a constrained one, or its system is singular.
  std::vector<int> parent(static_cast<std::size_t>(vertex_count));
  std::iota(parent.begin(), parent.end(), 0);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = representative(parent, mesh.faces(f, k));
      const int b = representative(parent, mesh.faces(f, (k + 1) % 3));
      if (a != b) parent[a] = b;
    }
  std::vector<bool> anchored(static_cast<std::size_t>(vertex_count), false);
  for (int v = 0; v < vertex_count; ++v)
    if (roles.role[v] != EditRoles::kFree) anchored[representative(parent, v)] = true;
  for (int v = 0; v < vertex_count; ++v)
    if (roles.role[v] == EditRoles::kFree && !anchored[representative(parent, v)])
      return "vertex " + std::to_string(v) +
             " lies in a connected part of the mesh with no fixed or handle vertex (its position "
             "would be undetermined): add one of its vertices to a set or leave the part out of "
             "the region of interest";
  std::vector<int> constrained;
  for (int v = 0; v < vertex_count; ++v)
    if (roles.role[v] != EditRoles::kFree) constrained.push_back(v);
  roles.constrained = Eigen::Map<const Eigen::VectorXi>(constrained.data(),
                                                        static_cast<Eigen::Index>(constrained.size()));
  return {};
}

}  // namespace harmonia::detail
