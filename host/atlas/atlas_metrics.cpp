#include "atlas/atlas_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "harmonia/types.h"
#include "mesh/power_of_two_scale.h"
#include "planar/exact_orientation.h"
#include "planar/uv_layout_checks.h"

namespace harmonia::detail {
namespace {

// The resolutions TextureAtlasOptions allows; at most 2^30 texels, so texel counts fit an int.
constexpr int kLargestResolution = 32768;

// ------------------------------------------------------------------------------ per triangle

struct SingularValues {
  double largest = 0.0;
  double smallest = 0.0;
};

// Singular values of the Jacobian J of the affine map from a 3D triangle (edges edge1, edge2 from
// corner 0, twice_area = |edge1 x edge2| > 0) to a UV triangle (edges uv_edge1, uv_edge2). Laid
// flat in its own frame (corner 0 at the origin, edge 1 along x, corner 2 above), the 3D edges are
// (l1, 0) and (edge1.edge2 / l1, twice_area / l1), which gives J's columns. Splitting J into a
// similarity z and an anti-similarity w: sigma1 = |z| + |w|, sigma2 = ||z| - |w||.
SingularValues jacobian_singular_values(const Eigen::Vector3d& edge1, const Eigen::Vector3d& edge2,
                                        double twice_area, const Eigen::Vector2d& uv_edge1,
                                        const Eigen::Vector2d& uv_edge2) {
  const double length1 = edge1.norm();
  const double along = edge1.dot(edge2) / length1;
  const double height = twice_area / length1;
  const Eigen::Vector2d image_of_x = uv_edge1 / length1;
  const Eigen::Vector2d image_of_y = (uv_edge2 - along * image_of_x) / height;
  const double similarity = std::hypot(0.5 * (image_of_x.x() + image_of_y.y()),
                                       0.5 * (image_of_x.y() - image_of_y.x()));
  const double anti_similarity = std::hypot(0.5 * (image_of_x.x() - image_of_y.y()),
                                            0.5 * (image_of_x.y() + image_of_y.x()));
  return {similarity + anti_similarity, std::abs(similarity - anti_similarity)};
}

// What the charts add up over their triangles.
struct ChartTotals {
  int counter_clockwise = 0;
  int clockwise = 0;
  int zero_area = 0;
  double area_3d = 0.0;  // every triangle, at the surface's safe-range scale
  double uv_area = 0.0;  // every triangle, texels^2
  // Over the measured triangles only (3D area as the weight):
  double weight = 0.0;
  double conformal_sum = 0.0;
  double area_log_sum = 0.0;        // with the chart's own scale
  double stretch_squared_sum = 0.0;
};

// ------------------------------------------------------------------------------ texels

// A UV triangle in texel units, counter-clockwise, with the texel columns and rows whose centres
// its bounding box may hold (clamped to the atlas).
struct TexelTriangle {
  double ax, ay, bx, by, cx, cy;
  int first_column, last_column, first_row, last_row;
};

// atlaseval's set-up of a triangle, expression for expression so that the same texel centres
// count as inside; nothing for a triangle of zero (or not finite) area or outside the atlas.
std::optional<TexelTriangle> texel_triangle(const TextureAtlas& atlas, Eigen::Index face) {
  const double width = atlas.resolution, height = atlas.height_texels();
  TexelTriangle t{};
  t.ax = atlas.corner_uv(face, 0) * width;
  t.ay = atlas.corner_uv(face, 1) * height;
  t.bx = atlas.corner_uv(face, 2) * width;
  t.by = atlas.corner_uv(face, 3) * height;
  t.cx = atlas.corner_uv(face, 4) * width;
  t.cy = atlas.corner_uv(face, 5) * height;
  const double twice_area = (t.bx - t.ax) * (t.cy - t.ay) - (t.by - t.ay) * (t.cx - t.ax);
  if (twice_area == 0.0 || !std::isfinite(twice_area)) return std::nullopt;
  if (twice_area < 0.0) {
    std::swap(t.bx, t.cx);
    std::swap(t.by, t.cy);
  }
  // Texel x has its centre at x + 0.5. Clamped as doubles first: a far-off corner must not
  // overflow the conversion to int.
  const double first_x = std::max(0.0, std::floor(std::min({t.ax, t.bx, t.cx}) - 0.5));
  const double last_x = std::min(width - 1.0, std::floor(std::max({t.ax, t.bx, t.cx}) - 0.5) + 1.0);
  const double first_y = std::max(0.0, std::floor(std::min({t.ay, t.by, t.cy}) - 0.5));
  const double last_y = std::min(height - 1.0, std::floor(std::max({t.ay, t.by, t.cy}) - 0.5) + 1.0);
  if (first_x > last_x || first_y > last_y) return std::nullopt;
  t.first_column = static_cast<int>(first_x);
  t.last_column = static_cast<int>(last_x);
  t.first_row = static_cast<int>(first_y);
  t.last_row = static_cast<int>(last_y);
  return t;
}

struct TexelCounts {
  std::int64_t covered = 0;
  std::int64_t overlapping = 0;
};

// On one page: texel centres strictly inside some triangle (covered) and inside triangles of two
// or more charts (overlapping). Every triangle is visited once over the texel centres of its bounding box,
// marking the chart that owns each centre in an image; a second chart turns the owner into
// kSeveralCharts, counted once. The image covers a band of rows at a time (at most 2^22 texels,
// 16 MiB, reused from band to band), each triangle entered in the bands its rows meet: a 32768^2
// atlas needs no 4 GiB image, and the memory the system has to map is the same at every size.
// Neither count depends on the order of the triangles.
TexelCounts count_texels(const TextureAtlas& atlas, int page) {
  constexpr std::int32_t kNoChart = -1;
  constexpr std::int32_t kSeveralCharts = -2;
  constexpr std::int64_t kBandTexels = std::int64_t{1} << 22;
  const int size = atlas.resolution;  // texels per row
  const int rows = atlas.height_texels();
  const int rows_per_band = static_cast<int>(std::max<std::int64_t>(1, kBandTexels / size));
  const int band_count = (rows + rows_per_band - 1) / rows_per_band;
  const Eigen::Index face_count = atlas.corner_uv.rows();

  // The faces of each band, in face order (a counting sort: count, offsets, fill).
  std::vector<int> band_start(static_cast<std::size_t>(band_count) + 1, 0);
  auto for_each_band = [&](Eigen::Index face, auto visit) {
    const int chart = atlas.chart_of_face[static_cast<std::size_t>(face)];
    if (chart < 0 || atlas.charts[static_cast<std::size_t>(chart)].page != page) return;
    const std::optional<TexelTriangle> triangle = texel_triangle(atlas, face);
    if (!triangle) return;
    for (int band = triangle->first_row / rows_per_band;
         band <= triangle->last_row / rows_per_band; ++band) {
      visit(band);
    }
  };
  for (Eigen::Index face = 0; face < face_count; ++face) {
    for_each_band(face, [&](int band) { ++band_start[static_cast<std::size_t>(band) + 1]; });
  }
  for (int band = 0; band < band_count; ++band) band_start[band + 1] += band_start[band];
  std::vector<int> band_faces(static_cast<std::size_t>(band_start.back()));
  std::vector<int> next_slot(band_start.begin(), band_start.end() - 1);
  for (Eigen::Index face = 0; face < face_count; ++face) {
    for_each_band(face, [&](int band) {
      band_faces[static_cast<std::size_t>(next_slot[band]++)] = static_cast<int>(face);
    });
  }

  TexelCounts counts;
  std::vector<std::int32_t> owner;
  for (int band = 0; band < band_count; ++band) {
    const int band_first_row = band * rows_per_band;
    const int band_last_row = std::min(rows, band_first_row + rows_per_band) - 1;
    owner.assign(static_cast<std::size_t>(band_last_row - band_first_row + 1) * size, kNoChart);
    for (int slot = band_start[band]; slot < band_start[band + 1]; ++slot) {
      const int face = band_faces[static_cast<std::size_t>(slot)];
      const std::int32_t chart = atlas.chart_of_face[static_cast<std::size_t>(face)];
      const TexelTriangle t = *texel_triangle(atlas, face);
      const int first_row = std::max(t.first_row, band_first_row);
      const int last_row = std::min(t.last_row, band_last_row);
      for (int y = first_row; y <= last_row; ++y) {
        const double py = y + 0.5;
        std::int32_t* row = owner.data() + static_cast<std::size_t>(y - band_first_row) * size;
        for (int x = t.first_column; x <= t.last_column; ++x) {
          const double px = x + 0.5;
          // Strictly left of all three edges of the counter-clockwise triangle.
          if ((t.bx - t.ax) * (py - t.ay) - (t.by - t.ay) * (px - t.ax) <= 0) continue;
          if ((t.cx - t.bx) * (py - t.by) - (t.cy - t.by) * (px - t.bx) <= 0) continue;
          if ((t.ax - t.cx) * (py - t.cy) - (t.ay - t.cy) * (px - t.cx) <= 0) continue;
          std::int32_t& texel = row[x];
          if (texel == kNoChart) {
            texel = chart;
            ++counts.covered;
          } else if (texel != chart && texel != kSeveralCharts) {
            texel = kSeveralCharts;
            ++counts.overlapping;
          }
        }
      }
    }
  }
  return counts;
}

// ------------------------------------------------------------------------------ boundaries

// Each segment has the other's two ends strictly on opposite sides of it (exact signs).
bool cross_properly(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                    const Eigen::Vector2d& q1, const Eigen::Vector2d& q2) {
  if (orientation_sign(p1, p2, q1) * orientation_sign(p1, p2, q2) >= 0) return false;
  return orientation_sign(q1, q2, p1) * orientation_sign(q1, q2, p2) < 0;
}

// The boundary edges of the layout: edges that one face uses once and no other face uses (as
// atlaseval counts them, an edge twice in one face is no boundary). The faces at each UV row are
// listed (a counting sort), and those at one end of an edge are searched for the edge: a UV row
// has only the few faces around its vertex in its chart, so this takes linear time.
std::vector<std::array<int, 2>> layout_boundary_edges(const AtlasUvLayout& layout) {
  const Eigen::Index face_count = layout.uv_faces.rows();
  std::vector<int> row_start(static_cast<std::size_t>(layout.uv.rows()) + 1, 0);
  for (Eigen::Index face = 0; face < face_count; ++face) {
    for (int corner = 0; corner < 3; ++corner) ++row_start[layout.uv_faces(face, corner) + 1];
  }
  for (std::size_t row = 1; row < row_start.size(); ++row) row_start[row] += row_start[row - 1];
  std::vector<int> faces_at_row(static_cast<std::size_t>(row_start.back()));
  std::vector<int> next_slot(row_start.begin(), row_start.end() - 1);
  for (Eigen::Index face = 0; face < face_count; ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      faces_at_row[next_slot[layout.uv_faces(face, corner)]++] = static_cast<int>(face);
    }
  }

  std::vector<std::array<int, 2>> edges;
  for (Eigen::Index face = 0; face < face_count; ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int from = layout.uv_faces(face, corner), to = layout.uv_faces(face, (corner + 1) % 3);
      if (from == to) continue;
      int uses = 0;
      for (int slot = row_start[from]; slot < row_start[from + 1]; ++slot) {
        const int other = faces_at_row[slot];
        if (slot > row_start[from] && other == faces_at_row[slot - 1]) continue;  // listed twice
        for (int k = 0; k < 3; ++k) {
          const int a = layout.uv_faces(other, k), b = layout.uv_faces(other, (k + 1) % 3);
          if ((a == from && b == to) || (a == to && b == from)) ++uses;
        }
      }
      if (uses == 1) edges.push_back({from, to});
    }
  }
  return edges;
}

// Pairs of boundary edges of the layout that cross properly, edges sharing a UV row left out.
// Found through a uniform grid: every edge is entered in the cells its bounding box covers, the
// entries sorted by cell, and a pair is tested in the first cell (lowest column, then row) that
// both cover, so once.
int count_boundary_crossings(const AtlasUvLayout& layout) {
  std::vector<std::array<int, 2>> edges = layout_boundary_edges(layout);
  // Edges with an end that is not finite cannot be placed in the grid (nor cross anything).
  std::erase_if(edges, [&](const std::array<int, 2>& edge) {
    return !layout.uv.row(edge[0]).allFinite() || !layout.uv.row(edge[1]).allFinite();
  });
  if (edges.size() < 2) return 0;

  Eigen::AlignedBox2d box;
  for (const auto& [from, to] : edges) {
    box.extend(layout.uv.row(from).transpose());
    box.extend(layout.uv.row(to).transpose());
  }
  // Measured at a power-of-two scale where lengths and the orientation products cannot overflow
  // (the same crossings: mesh/power_of_two_scale.h), whatever UVs a broken atlas holds.
  const double scale =
      safe_range_scale_for(box.min().cwiseAbs().cwiseMax(box.max().cwiseAbs()).maxCoeff());
  const Eigen::MatrixX2d scaled_uv =
      scale == 1.0 ? Eigen::MatrixX2d() : Eigen::MatrixX2d(layout.uv * scale);
  const Eigen::MatrixX2d& uv = scale == 1.0 ? layout.uv : scaled_uv;
  box = Eigen::AlignedBox2d(box.min() * scale, box.max() * scale);
  double total_length = 0.0;
  for (const auto& [from, to] : edges) total_length += (uv.row(to) - uv.row(from)).norm();

  // atlaseval's cells, twice the mean edge length; but large enough that the box holds about four
  // cells per edge at most, and 2^20 along a side, so that a few short edges far apart cannot make
  // a huge grid.
  constexpr double kMostCellsPerSide = 1 << 20;
  const double edge_count = static_cast<double>(edges.size());
  const Eigen::Vector2d extent = box.sizes();
  double cell_size = std::max({2.0 * total_length / edge_count,
                               std::sqrt(extent.x() * extent.y() / (4.0 * edge_count)),
                               extent.maxCoeff() / kMostCellsPerSide});
  if (!(cell_size > 0.0)) cell_size = 1.0;  // every edge has length zero at one point
  const std::int64_t columns = static_cast<std::int64_t>(std::floor(extent.x() / cell_size)) + 1;
  auto cell_of = [&](double value, double low) {
    return static_cast<std::int64_t>(std::floor((value - low) / cell_size));
  };

  struct CellRange {
    std::int64_t first_column, last_column, first_row, last_row;
  };
  struct Entry {
    std::int64_t cell;
    int edge;
    bool operator<(const Entry& other) const {
      return cell != other.cell ? cell < other.cell : edge < other.edge;
    }
  };
  std::vector<CellRange> ranges(edges.size());
  std::vector<Entry> entries;
  entries.reserve(edges.size() * 2);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const Eigen::Vector2d a = uv.row(edges[e][0]), b = uv.row(edges[e][1]);
    // floor((x - low) / h) is monotone in x, so overlapping boxes get overlapping cell ranges.
    CellRange& range = ranges[e];
    range = {cell_of(std::min(a.x(), b.x()), box.min().x()),
             cell_of(std::max(a.x(), b.x()), box.min().x()),
             cell_of(std::min(a.y(), b.y()), box.min().y()),
             cell_of(std::max(a.y(), b.y()), box.min().y())};
    for (std::int64_t row = range.first_row; row <= range.last_row; ++row) {
      for (std::int64_t column = range.first_column; column <= range.last_column; ++column) {
        entries.push_back({row * columns + column, static_cast<int>(e)});
      }
    }
  }
  std::sort(entries.begin(), entries.end());

  int crossings = 0;
  for (std::size_t begin = 0; begin < entries.size();) {
    std::size_t end = begin;
    while (end < entries.size() && entries[end].cell == entries[begin].cell) ++end;
    const std::int64_t row = entries[begin].cell / columns;
    const std::int64_t column = entries[begin].cell % columns;
    for (std::size_t i = begin; i < end; ++i) {
      const auto& [p, q] = edges[static_cast<std::size_t>(entries[i].edge)];
      const CellRange& range_pq = ranges[static_cast<std::size_t>(entries[i].edge)];
      for (std::size_t j = i + 1; j < end; ++j) {
        const auto& [r, s] = edges[static_cast<std::size_t>(entries[j].edge)];
        const CellRange& range_rs = ranges[static_cast<std::size_t>(entries[j].edge)];
        if (column != std::max(range_pq.first_column, range_rs.first_column) ||
            row != std::max(range_pq.first_row, range_rs.first_row)) {
          continue;
        }
        if (p == r || p == s || q == r || q == s) continue;
        if (cross_properly(uv.row(p), uv.row(q), uv.row(r), uv.row(s))) {
          ++crossings;
        }
      }
    }
    begin = end;
  }
  return crossings;
}

}  // namespace

// ------------------------------------------------------------------------------ the atlas

std::string atlas_mismatch(const Mesh& mesh, const TextureAtlas& atlas) {
  const Eigen::Index face_count = mesh.faces.rows();
  for (Eigen::Index face = 0; face < face_count; ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int vertex = mesh.faces(face, corner);
      if (vertex < 0 || vertex >= mesh.vertices.rows()) {
        return "face " + std::to_string(face) + " refers to vertex " + std::to_string(vertex) +
               ", but the mesh has " + std::to_string(mesh.vertices.rows()) + " vertices";
      }
    }
  }
  if (static_cast<Eigen::Index>(atlas.chart_of_face.size()) != face_count) {
    return "chart_of_face has " + std::to_string(atlas.chart_of_face.size()) +
           " entries but the mesh has " + std::to_string(face_count) + " faces";
  }
  if (atlas.corner_uv.rows() != face_count) {
    return "corner_uv has " + std::to_string(atlas.corner_uv.rows()) +
           " rows but the mesh has " + std::to_string(face_count) + " faces";
  }
  if (atlas.resolution < 1 || atlas.resolution > kLargestResolution) {
    return "resolution " + std::to_string(atlas.resolution) + " is outside 1.." +
           std::to_string(kLargestResolution);
  }
  if (atlas.height < 0 || atlas.height > kLargestResolution) {
    return "height " + std::to_string(atlas.height) + " is outside 0.." + std::to_string(kLargestResolution);
  }
  const int chart_count = static_cast<int>(atlas.charts.size());
  if (atlas.pages < 1) return "the atlas has " + std::to_string(atlas.pages) + " pages";
  for (int chart = 0; chart < chart_count; ++chart) {
    const int page = atlas.charts[static_cast<std::size_t>(chart)].page;
    if (page < 0 || page >= atlas.pages) {
      return "chart " + std::to_string(chart) + " is on page " + std::to_string(page) + ", but the atlas has " +
             std::to_string(atlas.pages);
    }
  }
  std::vector<char> listed(static_cast<std::size_t>(face_count), 0);
  for (int chart = 0; chart < chart_count; ++chart) {
    for (const int face : atlas.charts[static_cast<std::size_t>(chart)].faces) {
      auto listing = [&] {
        return "chart " + std::to_string(chart) + " lists face " + std::to_string(face);
      };
      if (face < 0 || face >= face_count) {
        return listing() + ", but the mesh has " + std::to_string(face_count) + " faces";
      }
      const int owner = atlas.chart_of_face[static_cast<std::size_t>(face)];
      if (owner != chart) return listing() + ", whose chart_of_face is " + std::to_string(owner);
      if (listed[static_cast<std::size_t>(face)] != 0) return listing() + " twice";
      listed[static_cast<std::size_t>(face)] = 1;
    }
  }
  for (Eigen::Index face = 0; face < face_count; ++face) {
    const int chart = atlas.chart_of_face[static_cast<std::size_t>(face)];
    if (chart < -1 || chart >= chart_count) {
      return "face " + std::to_string(face) + " is in chart " + std::to_string(chart) +
             ", but the atlas has " + std::to_string(chart_count) + " charts";
    }
    if (chart >= 0 && listed[static_cast<std::size_t>(face)] == 0) {
      return "face " + std::to_string(face) + " is in chart " + std::to_string(chart) +
             ", which does not list it";
    }
  }
  return {};
}

AtlasUvLayout atlas_uv_layout(const Mesh& mesh, const TextureAtlas& atlas) {
  const Eigen::Index face_count = mesh.faces.rows();
  // Per surface vertex, its UV rows made so far as a list, newest first: newest_row[vertex], then
  // previous_row[row]. A vertex has one row per chart around it (more only where a chart's corners
  // disagree), so the lists are short.
  std::vector<int> newest_row(static_cast<std::size_t>(mesh.vertices.rows()), -1);
  std::vector<int> previous_row;
  std::vector<int> row_chart;
  std::vector<Eigen::Vector2d> rows;
  // At most one row per corner; reserved (untouched pages cost nothing) rather than regrown.
  previous_row.reserve(static_cast<std::size_t>(face_count) * 3);
  row_chart.reserve(static_cast<std::size_t>(face_count) * 3);
  rows.reserve(static_cast<std::size_t>(face_count) * 3);
  AtlasUvLayout layout;
  layout.uv_faces.resize(face_count, 3);
  for (Eigen::Index face = 0; face < face_count; ++face) {
    const int chart = atlas.chart_of_face[static_cast<std::size_t>(face)];
    for (int corner = 0; corner < 3; ++corner) {
      const auto vertex = static_cast<std::size_t>(mesh.faces(face, corner));
      const Eigen::Vector2d uv(atlas.corner_uv(face, 2 * corner),
                               atlas.corner_uv(face, 2 * corner + 1));
      int row = newest_row[vertex];
      while (row >= 0 && !(row_chart[static_cast<std::size_t>(row)] == chart &&
                           rows[static_cast<std::size_t>(row)] == uv)) {
        row = previous_row[static_cast<std::size_t>(row)];
      }
      if (row < 0) {
        row = static_cast<int>(rows.size());
        rows.push_back(uv);
        row_chart.push_back(chart);
        previous_row.push_back(newest_row[vertex]);
        newest_row[vertex] = row;
      }
      layout.uv_faces(face, corner) = row;
    }
  }
  layout.uv.resize(static_cast<Eigen::Index>(rows.size()), 2);
  for (std::size_t row = 0; row < rows.size(); ++row) {
    layout.uv.row(static_cast<Eigen::Index>(row)) = rows[row].transpose();
  }
  return layout;
}

AtlasMetrics measure_atlas(const Mesh& mesh, TextureAtlas& atlas) {
  if (const std::string problem = atlas_mismatch(mesh, atlas); !problem.empty()) {
    throw Error(Status::invalid_input, "measure_atlas: " + problem);
  }
  const Eigen::Index face_count = mesh.faces.rows();
  const int chart_count = static_cast<int>(atlas.charts.size());
  // UV units to texels, along u and along v.
  const Eigen::Array2d texels_per_atlas_unit(atlas.resolution, atlas.height_texels());
  const double texel_area = texels_per_atlas_unit.prod();
  // 3D areas are taken at a power-of-two scale of the surface at which they neither overflow nor
  // underflow (exact: mesh/power_of_two_scale.h); every ratio is unchanged and the absolute
  // figures are scaled back.
  const double surface_scale =
      mesh.vertices.size() > 0 && mesh.vertices.allFinite()
          ? safe_range_scale_for(mesh.vertices.cwiseAbs().maxCoeff())
          : 1.0;
  auto position = [&](Eigen::Index face, int corner) -> Eigen::Vector3d {
    return mesh.vertices.row(mesh.faces(face, corner)).transpose() * surface_scale;
  };

  const AtlasUvLayout layout = atlas_uv_layout(mesh, atlas);
  const std::vector<double> signed_areas = signed_uv_areas(layout.uv, layout.uv_faces);
  AtlasMetrics metrics;
  metrics.charts = chart_count;
  metrics.faces = static_cast<int>(face_count);

  // First pass: orientation counts and areas per chart (the charts' scales need them all).
  std::vector<ChartTotals> totals(static_cast<std::size_t>(chart_count));
  std::vector<TriangleState> states(static_cast<std::size_t>(face_count),
                                    TriangleState::degenerate);
  double total_area_3d = 0.0, total_uv_area = 0.0;
  for (Eigen::Index face = 0; face < face_count; ++face) {
    const int chart = atlas.chart_of_face[static_cast<std::size_t>(face)];
    if (chart < 0) {
      ++metrics.dropped_faces;
      continue;
    }
    ChartTotals& chart_totals = totals[static_cast<std::size_t>(chart)];
    const TriangleState state = classify_uv_triangle(layout.uv, layout.uv_faces, face,
                                                     signed_areas[static_cast<std::size_t>(face)]);
    states[static_cast<std::size_t>(face)] = state;
    if (state == TriangleState::positive) ++chart_totals.counter_clockwise;
    if (state == TriangleState::flipped) ++chart_totals.clockwise;
    if (state == TriangleState::degenerate) ++chart_totals.zero_area;
    const Eigen::Vector3d edge1 = position(face, 1) - position(face, 0);
    const double area_3d = 0.5 * edge1.cross(position(face, 2) - position(face, 0)).norm();
    const double uv_area = std::abs(signed_areas[static_cast<std::size_t>(face)]) *
                           texel_area;
    if (std::isfinite(area_3d)) {
      chart_totals.area_3d += area_3d;
      total_area_3d += area_3d;
    }
    if (std::isfinite(uv_area)) {
      chart_totals.uv_area += uv_area;
      total_uv_area += uv_area;
    }
  }
  for (const ChartTotals& chart : totals) {
    metrics.flipped_triangles +=
        std::min(chart.counter_clockwise, chart.clockwise) + chart.zero_area;
    if (chart.clockwise > chart.counter_clockwise) ++metrics.mirrored_charts;
  }

  // Second pass: the distortions, each chart scaled so that its UV area equals its 3D area (and,
  // for the atlas' area distortion, the whole atlas by one scale). Scales are 3D area per texel^2.
  const double atlas_scale = total_uv_area > 0.0 ? total_area_3d / total_uv_area : 0.0;
  double weight = 0.0, conformal_sum = 0.0, atlas_area_log_sum = 0.0, stretch_squared_sum = 0.0;
  for (Eigen::Index face = 0; face < face_count; ++face) {
    const int chart = atlas.chart_of_face[static_cast<std::size_t>(face)];
    if (chart < 0 || states[static_cast<std::size_t>(face)] == TriangleState::degenerate) continue;
    const Eigen::Vector3d edge1 = position(face, 1) - position(face, 0);
    const Eigen::Vector3d edge2 = position(face, 2) - position(face, 0);
    const double twice_area = edge1.cross(edge2).norm();
    if (!(twice_area > 0.0) || !std::isfinite(twice_area) || !(edge1.norm() > 0.0)) continue;
    const Eigen::Vector2d uv0 = layout.uv.row(layout.uv_faces(face, 0));
    const Eigen::Vector2d uv1 = layout.uv.row(layout.uv_faces(face, 1));
    const Eigen::Vector2d uv2 = layout.uv.row(layout.uv_faces(face, 2));
    const SingularValues sigma =
        jacobian_singular_values(edge1, edge2, twice_area, ((uv1 - uv0).array() * texels_per_atlas_unit).matrix(),
                                 ((uv2 - uv0).array() * texels_per_atlas_unit).matrix());
    if (!(sigma.smallest > 0.0) || !std::isfinite(sigma.largest)) continue;
    const double area_3d = 0.5 * twice_area;
    const double uv_area = std::abs(signed_areas[static_cast<std::size_t>(face)]) *
                           texel_area;
    ChartTotals& chart_totals = totals[static_cast<std::size_t>(chart)];
    const double chart_scale = chart_totals.area_3d / chart_totals.uv_area;
    // Sander et al.: the map UV -> surface, scaled, has singular values 1 / (sqrt(scale) sigma2)
    // and 1 / (sqrt(scale) sigma1); its mean square stretch is half the sum of their squares.
    const double stretch_squared =
        0.5 / chart_scale *
        (1.0 / (sigma.smallest * sigma.smallest) + 1.0 / (sigma.largest * sigma.largest));
    const double conformal = sigma.largest / sigma.smallest;
    const double chart_area_log = std::abs(std::log(chart_scale * uv_area / area_3d));
    const double atlas_area_log = std::abs(std::log(atlas_scale * uv_area / area_3d));
    chart_totals.weight += area_3d;
    chart_totals.conformal_sum += area_3d * conformal;
    chart_totals.area_log_sum += area_3d * chart_area_log;
    chart_totals.stretch_squared_sum += area_3d * stretch_squared;
    weight += area_3d;
    conformal_sum += area_3d * conformal;
    atlas_area_log_sum += area_3d * atlas_area_log;
    stretch_squared_sum += area_3d * stretch_squared;
  }

  const double area_unit = surface_scale * surface_scale;  // 3D areas back to the model's units
  for (int chart = 0; chart < chart_count; ++chart) {
    const ChartTotals& chart_totals = totals[static_cast<std::size_t>(chart)];
    AtlasChart& target = atlas.charts[static_cast<std::size_t>(chart)];
    target.surface_area = chart_totals.area_3d / area_unit;
    const bool measured = chart_totals.weight > 0.0;
    target.l2_stretch =
        measured ? std::sqrt(chart_totals.stretch_squared_sum / chart_totals.weight) : 1.0;
    target.angle_distortion = measured ? chart_totals.conformal_sum / chart_totals.weight : 1.0;
    target.area_distortion = measured ? chart_totals.area_log_sum / chart_totals.weight : 0.0;
  }
  if (weight > 0.0) {
    metrics.l2_stretch = std::sqrt(stretch_squared_sum / weight);
    metrics.angle_distortion = conformal_sum / weight;
    metrics.area_distortion = atlas_area_log_sum / weight;
  }
  if (total_area_3d > 0.0 && total_uv_area > 0.0) {
    metrics.texels_per_unit = std::sqrt(total_uv_area / total_area_3d) * surface_scale;
  }

  // Texels page by page: charts on two pages share none.
  const double page_texels = texel_area;
  std::int64_t covered = 0;
  for (int page = 0; page < atlas.pages; ++page) {
    const TexelCounts texels = count_texels(atlas, page);
    metrics.overlapping_texels += static_cast<int>(texels.overlapping);
    metrics.page_coverage.push_back(static_cast<double>(texels.covered) / page_texels);
    covered += texels.covered;
  }
  metrics.coverage = static_cast<double>(covered) / (page_texels * atlas.pages);
  if (atlas.pages == 1) {
    metrics.boundary_crossings = count_boundary_crossings(layout);
  } else {
    // Page by page: the faces of each page's charts alone (a UV row belongs to one chart).
    for (int page = 0; page < atlas.pages; ++page) {
      AtlasUvLayout on_page;
      on_page.uv = layout.uv;
      on_page.uv_faces.resize(face_count, 3);
      Eigen::Index faces_on_page = 0;
      for (Eigen::Index face = 0; face < face_count; ++face) {
        const int chart = atlas.chart_of_face[static_cast<std::size_t>(face)];
        if (chart >= 0 && atlas.charts[static_cast<std::size_t>(chart)].page == page)
          on_page.uv_faces.row(faces_on_page++) = layout.uv_faces.row(face);
      }
      on_page.uv_faces.conservativeResize(faces_on_page, 3);
      metrics.boundary_crossings += count_boundary_crossings(on_page);
    }
  }
  return metrics;
}

}  // namespace harmonia::detail
