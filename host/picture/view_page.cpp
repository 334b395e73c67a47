// The view page (harmonia/view_page.h): the layouts' data as JSON inside the page's template, with
// three.js, the orbit controls and the page's script and style (view_assets.h) put in its place.
//
// The data. Per layout, the arrays the page draws from (positions, faces, UVs, UV faces, chart per
// face, turned-over per face, and one value per face for each colour field) are little-endian
// typed arrays in base64, so that a million faces take about 60 bytes each on the page rather
// than the hundreds a JSON number list takes; the figures (per chart, per layout, the headline)
// are plain JSON. The page's script (host/picture/view/viewer.js) documents what it reads.

#include "harmonia/view_page.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "harmonia/distortion_plot.h"
#include "harmonia/metrics.h"
#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "picture/view_assets.h"
#include "planar/uv_layout_checks.h"

namespace harmonia {
namespace {

using Json = nlohmann::json;

static_assert(std::endian::native == std::endian::little, "the page reads little-endian arrays");

// RFC 4648 base64 of `size` bytes.
std::string base64(const void* data, std::size_t size) {
  static constexpr char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string text;
  text.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const std::uint32_t b0 = bytes[i], b1 = i + 1 < size ? bytes[i + 1] : 0u, b2 = i + 2 < size ? bytes[i + 2] : 0u;
    const std::uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    text += alphabet[(triple >> 18) & 63];
    text += alphabet[(triple >> 12) & 63];
    text += i + 1 < size ? alphabet[(triple >> 6) & 63] : '=';
    text += i + 2 < size ? alphabet[triple & 63] : '=';
  }
  return text;
}

template <typename T>
std::string base64_of(const std::vector<T>& values) {
  return base64(values.data(), values.size() * sizeof(T));
}

// The charts of a layout: its own ids, or the faces connected through shared UV vertices (a
// union-find over the UV vertices), numbered in the order of their first face.
std::vector<std::int32_t> charts_of(const ViewLayout& layout, int& chart_count) {
  const auto face_count = static_cast<std::size_t>(layout.uv_faces.rows());
  std::vector<std::int32_t> chart(face_count);
  chart_count = 0;
  if (!layout.chart_of_face.empty()) {
    if (layout.chart_of_face.size() != face_count)
      throw Error(Status::invalid_input, "view page: layout \"" + layout.name + "\" has " +
                                             std::to_string(layout.chart_of_face.size()) + " chart ids for " +
                                             std::to_string(face_count) + " faces");
    for (std::size_t f = 0; f < face_count; ++f) {
      if (layout.chart_of_face[f] < 0)
        throw Error(Status::invalid_input, "view page: layout \"" + layout.name + "\": face " + std::to_string(f) +
                                               " has chart id " + std::to_string(layout.chart_of_face[f]));
      chart[f] = layout.chart_of_face[f];
      chart_count = std::max(chart_count, chart[f] + 1);
    }
    return chart;
  }
  std::vector<int> parent(static_cast<std::size_t>(layout.uv.rows()));
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v) {
      parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
      v = parent[static_cast<std::size_t>(v)];
    }
    return v;
  };
  for (Eigen::Index f = 0; f < layout.uv_faces.rows(); ++f)
    for (int k = 1; k < 3; ++k) parent[static_cast<std::size_t>(root(layout.uv_faces(f, k)))] = root(layout.uv_faces(f, 0));
  std::vector<int> number(parent.size(), -1);
  for (Eigen::Index f = 0; f < layout.uv_faces.rows(); ++f) {
    int& id = number[static_cast<std::size_t>(root(layout.uv_faces(f, 0)))];
    if (id < 0) id = chart_count++;
    chart[static_cast<std::size_t>(f)] = id;
  }
  return chart;
}

// One colour field of one layout: a value per face (NaN where undefined).
struct Field {
  const char* name;
  const char* key;
  std::vector<float> values;
};

// The value below which `share` of the finite values lie (0 when there is none).
double quantile(std::vector<double> values, double share) {
  std::erase_if(values, [](double value) { return !std::isfinite(value); });
  if (values.empty()) return 0.0;
  const auto at = values.begin() + static_cast<std::ptrdiff_t>(share * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

// Four significant digits, as the colour bar prints them.
double rounded(double value) {
  if (value == 0.0 || !std::isfinite(value)) return value;
  const double scale = std::pow(10.0, 3 - std::floor(std::log10(std::abs(value))));
  return std::round(value * scale) / scale;
}

struct LayoutData {
  Json json;
  std::vector<Field> fields;
};

LayoutData layout_data(const ViewLayout& layout) {
  const Mesh& mesh = layout.mesh3d;
  if (layout.uv_faces.rows() != mesh.faces.rows())
    throw Error(Status::invalid_input, "view page: layout \"" + layout.name + "\" has " +
                                           std::to_string(layout.uv_faces.rows()) + " UV faces for " +
                                           std::to_string(mesh.faces.rows()) + " faces of its mesh");
  const DistortionMetrics metrics = evaluate_map(mesh, layout.uv, layout.uv_faces);
  const Eigen::VectorXd angle = face_angle_distortion(mesh, layout.uv, layout.uv_faces);
  const std::vector<double> uv_areas = detail::signed_uv_areas(layout.uv, layout.uv_faces);
  const auto face_count = static_cast<std::size_t>(mesh.faces.rows());

  int chart_count = 0;
  const std::vector<std::int32_t> chart = charts_of(layout, chart_count);
  std::vector<std::uint8_t> turned(face_count, 0);
  // Per chart: faces, and the sums that give its own L2 stretch with the chart scaled to its 3D
  // area (atlaseval.py's definition): sum A s^2, sum A, sum of UV areas.
  std::vector<int> chart_faces(static_cast<std::size_t>(chart_count), 0);
  std::vector<double> stretch_sum(chart_faces.size(), 0.0), area_3d(chart_faces.size(), 0.0),
      area_uv(chart_faces.size(), 0.0);
  double total_3d = 0.0, total_uv = 0.0;
  for (std::size_t f = 0; f < face_count; ++f) {
    const auto face = static_cast<Eigen::Index>(f);
    turned[f] = detail::classify_uv_triangle(layout.uv, layout.uv_faces, face, uv_areas[f]) !=
                detail::TriangleState::positive;
    const Eigen::Vector3d p0 = mesh.vertices.row(mesh.faces(face, 0)), p1 = mesh.vertices.row(mesh.faces(face, 1)),
                          p2 = mesh.vertices.row(mesh.faces(face, 2));
    const double area = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    const auto c = static_cast<std::size_t>(chart[f]);
    ++chart_faces[c];
    const double stretch = metrics.face_l2_stretch[face];
    if (std::isfinite(stretch) && std::isfinite(area) && std::isfinite(uv_areas[f])) {
      stretch_sum[c] += area * stretch * stretch;
      area_3d[c] += area;
      area_uv[c] += std::abs(uv_areas[f]);
      total_3d += area;
      total_uv += std::abs(uv_areas[f]);
    }
  }
  Json charts = Json::array();
  for (std::size_t c = 0; c < chart_faces.size(); ++c) {
    // face_l2_stretch is normalized by the layout's one scale; rescaled to the chart's own.
    double l2 = 0.0;
    if (area_3d[c] > 0.0 && area_uv[c] > 0.0 && total_3d > 0.0 && total_uv > 0.0)
      l2 = std::sqrt(stretch_sum[c] / area_3d[c] * (area_uv[c] / area_3d[c]) / (total_uv / total_3d));
    charts.push_back({{"id", c}, {"faces", chart_faces[c]}, {"l2_stretch", rounded(l2)}});
  }

  LayoutData data;
  const auto floats = [&](const Eigen::VectorXd& values) {
    std::vector<float> out(face_count);
    for (std::size_t f = 0; f < face_count; ++f) out[f] = static_cast<float>(values[static_cast<Eigen::Index>(f)]);
    return out;
  };
  data.fields.push_back({"angle distortion", "angle", floats(angle)});
  data.fields.push_back({"area distortion (log ratio)", "area", floats(metrics.face_area_log_ratio)});
  data.fields.push_back({"L2 stretch", "stretch", floats(metrics.face_l2_stretch)});

  std::vector<float> positions(static_cast<std::size_t>(mesh.vertices.size()));
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    for (int k = 0; k < 3; ++k) positions[static_cast<std::size_t>(3 * v + k)] = static_cast<float>(mesh.vertices(v, k));
  std::vector<float> uvs(static_cast<std::size_t>(layout.uv.size()));
  for (Eigen::Index v = 0; v < layout.uv.rows(); ++v)
    for (int k = 0; k < 2; ++k) uvs[static_cast<std::size_t>(2 * v + k)] = static_cast<float>(layout.uv(v, k));
  std::vector<std::uint32_t> faces(3 * face_count), uv_faces(3 * face_count);
  for (std::size_t f = 0; f < face_count; ++f)
    for (int k = 0; k < 3; ++k) {
      faces[3 * f + static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(mesh.faces(static_cast<Eigen::Index>(f), k));
      uv_faces[3 * f + static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(layout.uv_faces(static_cast<Eigen::Index>(f), k));
    }

  const auto figure = [](double value, int digits) {
    std::ostringstream text;
    text.precision(digits);
    text << std::fixed << value;
    return text.str();
  };
  const int flipped = metrics.flipped_triangles + metrics.zero_area_triangles;
  data.json = {
      {"name", layout.name},
      {"method", layout.method},
      {"kind", "uv"},
      {"vertex_count", mesh.vertices.rows()},
      {"face_count", mesh.faces.rows()},
      {"uv_count", layout.uv.rows()},
      {"positions", base64_of(positions)},
      {"faces", base64_of(faces)},
      {"uvs", base64_of(uvs)},
      {"uv_faces", base64_of(uv_faces)},
      {"chart", base64_of(chart)},
      {"flipped", base64_of(turned)},
      {"charts", std::move(charts)},
      {"figures",
       Json::array({Json::array({"charts", std::to_string(chart_count)}),
                    Json::array({"faces", std::to_string(mesh.faces.rows())}),
                    Json::array({"L2 stretch", figure(metrics.l2_stretch, 4)}),
                    Json::array({"conformal distortion", figure(metrics.conformal_distortion_mean, 4)}),
                    Json::array({"area distortion", figure(metrics.area_distortion_mean, 4)}),
                    Json::array({"turned over", std::to_string(flipped)})})},
  };
  return data;
}

// The ends of each field's colour bar, over every layout: from the 2nd to the 98th percentile, so
// that a few extreme triangles do not wash out the rest, and always including an isometry's value
// (0, or 1 for the stretch); symmetric about 0 for the log area ratio.
void add_fields(std::vector<LayoutData>& layouts) {
  const std::size_t field_count = layouts.front().fields.size();
  for (std::size_t k = 0; k < field_count; ++k) {
    const std::string_view key = layouts.front().fields[k].key;
    const bool symmetric = key == "area";
    std::vector<double> values;
    for (const LayoutData& layout : layouts)
      for (const float value : layout.fields[k].values) values.push_back(symmetric ? std::abs(value) : value);
    const double isometry = key == "stretch" ? 1.0 : 0.0;
    double low = symmetric ? 0.0 : rounded(std::min(quantile(values, 0.02), isometry));
    double high = rounded(std::max(quantile(std::move(values), 0.98), isometry));
    if (!(high > low)) high = low + (key == "stretch" ? 0.01 : 0.1);  // a flawless layout: a short bar
    if (symmetric) low = -high;
    for (LayoutData& layout : layouts) {
      const Field& field = layout.fields[k];
      Json entry = {{"name", field.name}, {"key", field.key}, {"values", base64_of(field.values)},
                    {"low", low}, {"high", high}};
      if (symmetric) entry["symmetric"] = true;
      layout.json["fields"].push_back(std::move(entry));
    }
  }
}

std::string_view text_of(const unsigned char* bytes, std::size_t size) {
  return {reinterpret_cast<const char*>(bytes), size};
}

// The template with each placeholder (there exactly once) replaced by its contents, assembled in
// one pass over the template, so that no inserted text is searched for placeholders again.
std::string filled(std::string_view page, std::vector<std::pair<std::string_view, std::string>> parts) {
  std::vector<std::pair<std::size_t, std::size_t>> at;  // (position in the template, part)
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::size_t first = page.find(parts[k].first);
    if (first == std::string_view::npos || page.find(parts[k].first, first + 1) != std::string_view::npos)
      throw Error(Status::unsupported,
                  "view page: this build's page template holds " + std::string(parts[k].first) + " other than once");
    at.emplace_back(first, k);
  }
  std::sort(at.begin(), at.end());
  std::string out;
  std::size_t from = 0;
  for (const auto& [position, k] : at) {
    out.append(page.substr(from, position - from));
    out += parts[k].second;
    from = position + parts[k].first.size();
  }
  out.append(page.substr(from));
  return out;
}

std::string html_escaped(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

void write_view_page(const std::filesystem::path& path, const std::vector<ViewLayout>& layouts,
                     const ViewPageOptions& options) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  if (extension != ".html" && extension != ".htm")
    throw Error(Status::io_error, "view page: " + path.string() + " is not an .html file (a page is HTML only)");
  detail::check_writable(path);
  if (layouts.empty()) throw Error(Status::invalid_input, "view page: there is no layout to show");
  std::vector<LayoutData> data;
  data.reserve(layouts.size());
  for (const ViewLayout& layout : layouts) data.push_back(layout_data(layout));
  add_fields(data);
  Json document = {{"title", options.title}, {"headline", Json::array()}, {"results", Json::array()}};
  for (const auto& [label, value] : options.headline) document["headline"].push_back({label, value});
  for (LayoutData& layout : data) document["results"].push_back(std::move(layout.json));
  // Inside a <script> element "</script" or "<!--" would end or change it: every "<", which JSON
  // has only inside strings, is written as the escape \u003c, which reads back the same.
  std::string json;
  for (const char c : document.dump()) {
    if (c == '<') json += "\\u003c";
    else json += c;
  }

  const std::string page = filled(
      text_of(detail::view_page_html, detail::view_page_html_size),
      {{"HARMONIA_TITLE", html_escaped(options.title.empty() ? "harmonia view" : options.title)},
       {"/*HARMONIA_VIEWER_CSS*/", std::string(text_of(detail::viewer_css, detail::viewer_css_size))},
       {"/*HARMONIA_THREE_JS*/",
        "/* three.js r111 (Debian's libjs-three), https://threejs.org: Copyright 2010-2019 three.js\n"
        "   authors, MIT licence (https://github.com/mrdoob/three.js/blob/dev/LICENSE). */\n" +
            std::string(text_of(detail::three_min_js, detail::three_min_js_size))},
       {"/*HARMONIA_ORBIT_CONTROLS_JS*/", std::string(text_of(detail::orbit_controls_js, detail::orbit_controls_js_size))},
       {"/*HARMONIA_VIEWER_JS*/", std::string(text_of(detail::viewer_js, detail::viewer_js_size))},
       {"/*HARMONIA_DATA_JSON*/", std::move(json)}});
  detail::write_file_atomically(path, page);
}

}  // namespace harmonia
