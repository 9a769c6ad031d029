// The `ispq` command line: one binary, one subcommand per task.
//
//   ispq stats FILE [--json]
//
// Flags may appear anywhere after the subcommand; `ispq --help` lists them.
#include <iostream>
#include <string>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/flags/usage.h"
#include "client/exit_codes.h"
#include "client/stats_command.h"

ABSL_FLAG(bool, json, false, "print machine-readable JSON instead of text");

namespace {

constexpr char kUsage[] =
    "ispq: quantize T-meshes for hexahedral meshing.\n"
    "usage:\n"
    "  ispq stats FILE [--json]   validate a T-mesh and print its counts\n";

}  // namespace

int main(int argc, char** argv) {
  absl::SetProgramUsageMessage(kUsage);
  const std::vector<char*> args = absl::ParseCommandLine(argc, argv);
  if (args.size() < 2) {
    std::cerr << kUsage;
    return ispq::cli::kExitUsage;
  }
  const std::string command = args[1];
  if (command == "stats") {
    if (args.size() != 3) {
      std::cerr << "usage: ispq stats FILE [--json]\n";
      return ispq::cli::kExitUsage;
    }
    return ispq::cli::RunStatsCommand(args[2], absl::GetFlag(FLAGS_json));
  }
  std::cerr << "ispq: unknown command '" << command << "'\n" << kUsage;
  return ispq::cli::kExitUsage;
}
