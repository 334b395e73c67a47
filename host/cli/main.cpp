// The `harmonia` command-line program: one subcommand per job (docs/cli.md).
// Every failure ends with one line "harmonia: <reason>" on stderr and a documented exit code.

#include <iostream>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/atlas.h"
#include "cli/batch.h"
#include "cli/common.h"
#include "cli/compare.h"
#include "cli/cut.h"
#include "cli/deform.h"
#include "cli/demo.h"
#include "cli/eval.h"
#include "cli/view.h"
#include "cli/info.h"
#include "cli/sphere.h"
#include "cli/transfer.h"
#include "cli/unwrap.h"
#include "harmonia/blas_threads.h"
#include "harmonia/io.h"

namespace {

using harmonia::cli::ExitCode;

int exit_with(ExitCode code, const std::string& reason) {
  std::cerr << "harmonia: " << reason << '\n';
  return static_cast<int>(code);
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = harmonia::cli;
  // The program owns its process: harmonia may hold OpenBLAS's process-wide thread count while it
  // factorizes two halves of a large system side by side (harmonia/blas_threads.h).
  harmonia::set_blas_thread_policy(harmonia::BlasThreadPolicy::hold_during_split_factorizations);
  // Interrupted (Ctrl-C, kill), it leaves no unfinished output file behind.
  harmonia::remove_unfinished_outputs_on_signals();
  CLI::App app{
      "harmonia: flatten triangle meshes (discrete conformal, LSCM, quasi-harmonic maps, "
      "ABF and linear ABF), map closed ones onto the sphere, and make texture atlases of any mesh, "
      "also of many at a time\nExit codes: 0 ok, 1 usage, 2 input/topology, 3 invalid result "
      "(flips), 4 numerical, 5 environment (I/O, device)",
      "harmonia"};
  app.require_subcommand(1);
  app.fallthrough();  // Global flags may follow the subcommand: `harmonia unwrap ... --quiet`.

  cli::GlobalOptions global;
  app.add_flag("-q,--quiet", global.quiet, "No progress line and no notes on stderr");
  app.add_flag("--progress", global.progress,
               "Show the progress line even if stderr is no terminal");
  app.add_flag("-v,--verbose", global.verbose,
               "Print each solver stage on its own line of stderr (abf: one per Newton step, "
               "with its constraint violation)");
  std::string gltf_mesh;
  app.add_option("--mesh", gltf_mesh,
                 "glTF input: read this mesh only (its name or index; in the world frame of its "
                 "first instance), not the whole default scene; for `atlas` with glTF output: "
                 "make the atlas of this mesh only");

  cli::InfoOptions info;
  cli::CutCommandOptions cut;
  cli::UnwrapOptions unwrap;
  cli::EvalOptions eval;
  cli::CompareOptions compare;
  cli::DemoOptions demo;
  cli::DeformOptions deform;
  cli::TransferOptions transfer;
  cli::SphereOptions sphere;
  cli::AtlasOptions atlas;
  cli::BatchOptions batch;
  cli::ViewOptions view;
  CLI::App* info_command = cli::add_info_command(app, info);
  CLI::App* cut_command = cli::add_cut_command(app, cut);
  CLI::App* unwrap_command = cli::add_unwrap_command(app, unwrap);
  CLI::App* eval_command = cli::add_eval_command(app, eval);
  CLI::App* compare_command = cli::add_compare_command(app, compare);
  CLI::App* demo_command = cli::add_demo_command(app, demo);
  CLI::App* sphere_command = cli::add_sphere_command(app, sphere);
  CLI::App* deform_command = cli::add_deform_command(app, deform);
  CLI::App* transfer_command = cli::add_transfer_command(app, transfer);
  CLI::App* atlas_command = cli::add_atlas_command(app, atlas);
  CLI::App* batch_command = cli::add_batch_command(app, batch);
  CLI::App* view_command = cli::add_view_command(app, view);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForAllHelp& help) {
    return app.exit(help);
  } catch (const CLI::ParseError& error) {
    return exit_with(ExitCode::usage, std::string(error.what()) + " (see `harmonia --help`)");
  }

  cli::choose_gltf_mesh(gltf_mesh);
  try {
    ExitCode code = ExitCode::ok;
    if (info_command->parsed()) code = cli::run_info(info, global);
    if (cut_command->parsed()) code = cli::run_cut(cut, global);
    if (unwrap_command->parsed()) code = cli::run_unwrap(unwrap, global);
    if (eval_command->parsed()) code = cli::run_eval(eval, global);
    if (compare_command->parsed()) code = cli::run_compare(compare, global);
    if (demo_command->parsed()) code = cli::run_demo(demo, global);
    if (sphere_command->parsed()) code = cli::run_sphere(sphere, global);
    if (deform_command->parsed()) code = cli::run_deform(deform, global);
    if (transfer_command->parsed()) code = cli::run_transfer(transfer, global);
    if (atlas_command->parsed()) code = cli::run_atlas(atlas, global);
    if (batch_command->parsed()) code = cli::run_batch(batch, global);
    if (view_command->parsed()) code = cli::run_view(view, global);
    return static_cast<int>(code);
  } catch (const cli::CliFailure& failure) {
    return exit_with(failure.code(), failure.what());
  } catch (const harmonia::Error& error) {
    return exit_with(cli::exit_code_for(error.status()), error.what());
  } catch (const std::bad_alloc&) {
    return exit_with(ExitCode::environment, "out of memory");
  } catch (const std::exception& error) {
    return exit_with(ExitCode::numerical, std::string("unexpected failure: ") + error.what());
  }
}
