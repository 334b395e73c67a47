#pragma once
// What every fuzz harness does with its input, and the checks that make a wrong answer as loud as a
// crash: the parser must accept or throw the documented error, and a mesh it accepts goes through
// the topology report, the index check, the strict cleanup and the repairing one, each followed by
// what the library promises of its result (harmonia/cleanup.h, harmonia/topology.h). A broken
// promise aborts, so libFuzzer reports it with its input.

#include <functional>
#include <string_view>

#include "harmonia/mesh.h"

namespace harmonia::fuzz {

//! The file name the harnesses give their parsers (error messages must start with it).
inline constexpr std::string_view input_name = "fuzz-input";

using Parser = std::function<Mesh(std::string_view contents, std::string_view name)>;

//! Parses `contents` and, when the parser accepts, runs check_accepted_mesh. A refusal must be
//! harmonia::Error with Status::parse_error and a message starting with input_name; any other
//! exception or status aborts.
void parse_and_check(std::string_view contents, const Parser& parse);

//! The topology report and both cleanups of an accepted mesh, and their promises.
void check_accepted_mesh(const Mesh& mesh);

//! Reports a broken promise (a finding) to the finding handler, which must not return: by default
//! it prints `what` and aborts, so that libFuzzer keeps the input.
[[noreturn]] void finding(std::string_view what);

using FindingHandler = void (*)(std::string_view what);
//! Installs the handler for findings (null: the default); returns the previous one. The test
//! suite's handler throws, so that a replayed finding fails one test instead of the program.
FindingHandler set_finding_handler(FindingHandler handler);

}  // namespace harmonia::fuzz
