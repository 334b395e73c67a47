// Marker files (harmonia/marker_file.h).

#include "harmonia/marker_file.h"

#include <fstream>
#include <set>
#include <sstream>

namespace harmonia {

std::vector<MarkerPair> parse_markers(const std::string& text, int source_vertices,
                                      int target_vertices, const std::string& source) {
  std::vector<MarkerPair> pairs;
  std::set<int> used_source, used_target;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const std::string content = line.substr(0, line.find('#'));
    std::istringstream fields(content);
    std::string first;
    if (!(fields >> first)) continue;  // blank or comment
    const std::string where = source + ":" + std::to_string(number) + ": ";
    std::istringstream pair_text(content);
    long long source_vertex = 0, target_vertex = 0;
    std::string extra;
    if (!(pair_text >> source_vertex >> target_vertex) || (pair_text >> extra))
      throw Error(Status::parse_error,
                  where + "expected two vertex indices \"sourceVertex targetVertex\", got \"" +
                      content + "\"");
    if (source_vertex < 0 || source_vertex >= source_vertices)
      throw Error(Status::invalid_input, where + "source vertex " + std::to_string(source_vertex) +
                                             " is outside the source mesh's " +
                                             std::to_string(source_vertices) + " vertices");
    if (target_vertex < 0 || target_vertex >= target_vertices)
      throw Error(Status::invalid_input, where + "target vertex " + std::to_string(target_vertex) +
                                             " is outside the target mesh's " +
                                             std::to_string(target_vertices) + " vertices");
    if (!used_source.insert(static_cast<int>(source_vertex)).second)
      throw Error(Status::invalid_input, where + "source vertex " + std::to_string(source_vertex) +
                                             " is already a marker of an earlier pair");
    if (!used_target.insert(static_cast<int>(target_vertex)).second)
      throw Error(Status::invalid_input, where + "target vertex " + std::to_string(target_vertex) +
                                             " is already a marker of an earlier pair");
    pairs.push_back({static_cast<int>(source_vertex), static_cast<int>(target_vertex)});
  }
  if (pairs.size() < 3)
    throw Error(Status::invalid_input, source + ": " + std::to_string(pairs.size()) +
                                           " marker pairs; deformation transfer needs at least 3");
  return pairs;
}

std::vector<MarkerPair> read_marker_file(const std::filesystem::path& path, int source_vertices,
                                         int target_vertices) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(Status::io_error, "cannot read marker file " + path.string());
  std::ostringstream text;
  text << file.rdbuf();
  return parse_markers(text.str(), source_vertices, target_vertices, path.string());
}

}  // namespace harmonia
