// A texture atlas of every mesh file in a folder, one file after another (each atlas already
// flattens its charts on every core): a line per file as it is done, a summary at the end. A file
// that fails is reported on its line and the batch goes on.
//   batch_over_a_folder IN_FOLDER OUT_FOLDER
// Writes OUT_FOLDER/NAME.obj for NAME.obj, OUT_FOLDER/NAME.ply.obj for NAME.ply, and so on.
// Exit status 0 when every file was done, 1 when any failed, 2 for a wrong call.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <harmonia/atlas_io.h>
#include <harmonia/io.h>
#include <harmonia/texture_atlas.h>

namespace {

namespace fs = std::filesystem;

// The files of `folder` the library reads (it knows them by their extension), sorted by name.
std::vector<fs::path> mesh_files_in(const fs::path& folder) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    try {
      (void)harmonia::format_from_extension(entry.path());
      files.push_back(entry.path());
    } catch (const harmonia::Error&) {
      // Not a mesh file (a README, a picture): not part of the batch.
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The atlas of one file, written to `output`; returns its number of charts. Every failure is
// thrown (harmonia::Error for the library's), so that the caller has one place to report it.
int write_atlas_of(const fs::path& input, const fs::path& output) {
  const harmonia::Mesh mesh = harmonia::read_mesh(input);
  harmonia::TextureAtlasOptions options;
  options.resolution = 1024;
  const harmonia::TextureAtlas atlas = harmonia::texture_atlas(mesh, options);
  if (!atlas.report.ok()) throw harmonia::Error(atlas.report.status, atlas.report.message);
  harmonia::write_atlas_obj(output, mesh, atlas);
  return atlas.metrics.charts;
}

// The first line of a message: one line per file, whatever the reason says.
std::string first_line(const std::string& message) { return message.substr(0, message.find('\n')); }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: batch_over_a_folder IN_FOLDER OUT_FOLDER\n");
    return 2;
  }
  const fs::path in_folder = argv[1], out_folder = argv[2];
  std::vector<fs::path> inputs;
  try {
    inputs = mesh_files_in(in_folder);
    fs::create_directories(out_folder);
    if (fs::equivalent(in_folder, out_folder))  // an output NAME.obj would replace its input
      throw std::runtime_error("the output folder must not be the input folder");
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 2;
  }

  using Clock = std::chrono::steady_clock;
  const Clock::time_point batch_start = Clock::now();
  std::size_t failed = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const std::string name = inputs[i].filename().string();
    const fs::path output = out_folder / (inputs[i].extension() == ".obj" ? name : name + ".obj");
    std::printf("[%zu/%zu] %-24s ", i + 1, inputs.size(), name.c_str());
    std::fflush(stdout);  // the name shows while the file is worked on
    const Clock::time_point start = Clock::now();
    try {
      const int charts = write_atlas_of(inputs[i], output);
      const std::chrono::duration<double> seconds = Clock::now() - start;
      std::printf("ok  %5.2f s  %d charts\n", seconds.count(), charts);
    } catch (const std::exception& error) {  // this file only: the batch goes on
      ++failed;
      std::printf("failed: %s\n", first_line(error.what()).c_str());
    }
  }
  const std::chrono::duration<double> seconds = Clock::now() - batch_start;
  std::printf("%zu files: %zu done, %zu failed, %.2f s\n", inputs.size(), inputs.size() - failed,
              failed, seconds.count());
  return failed == 0 ? 0 : 1;
}
