// SPDX-License-Identifier: Apache-2.0
// The `ispq` command line: one binary, one subcommand per task.
//
//   ispq stats FILE [--json]
//   ispq quantize FILE (--local | --server HOST:PORT) (--level P | --scaling S | --target-hexes N)
//        [--method isp|exact] [--lower-bound auto|on|off] [--mixed-sign=B]
//        [--time-limit SECONDS] [--out RESULT.json] [--json]
//   ispq validate FILE --result RESULT.json [--level P | --scaling S]
//   ispq submit FILE | watch JOB | cancel JOB | jobs | health | server-stats  [--server ...]
//   ispq batch DIR_OR_FILES... (--level P | --levels P,P,...) --out-dir DIR [--concurrency N]
//
// Flags may appear anywhere after the subcommand and may be spelled with dashes or underscores
// (--time-limit or --time_limit); `ispq --help` lists them.
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/flags/usage.h"
#include "absl/strings/numbers.h"
#include "absl/time/time.h"
#include "client/batch_command.h"
#include "client/exit_codes.h"
#include "client/job_commands.h"
#include "client/quantize_command.h"
#include "client/remote_command_options.h"
#include "client/server_commands.h"
#include "client/stats_command.h"
#include "client/validate_command.h"
#include "core/large_allocations.h"

ABSL_FLAG(bool, json, false, "print machine-readable JSON instead of text");
ABSL_FLAG(bool, local, false, "quantize in-process instead of on a server");
ABSL_FLAG(int32_t, level, -1, "resolution level in percent: 0, 1, 5, 10, 17, 25, 50 or 100");
ABSL_FLAG(double, scaling, 0, "scaling factor s: targets are s * arc length");
ABSL_FLAG(int64_t, target_hexes, 0, "choose s so that the mesh has about this many hexes");
ABSL_FLAG(bool, mixed_sign, true, "allow mixed-sign sheets (paper section 4.3.3)");
ABSL_FLAG(bool, decompose, true, "solve independent subproblems separately");
ABSL_FLAG(bool, per_arc_nonnegative, false, "also require every arc length to be >= 0");
ABSL_FLAG(bool, reference_block_boxes, false,
          "separation search in the reference implementation's compatibility mode");
ABSL_FLAG(double, time_limit, 0, "stop after this many seconds with the best valid result");
ABSL_FLAG(std::string, method, "isp",
          "isp (the Integer-Sheet-Pump) or exact (ISP, then a MILP until proven optimal or the "
          "time limit, default 60 s)");
ABSL_FLAG(std::string, lower_bound, "auto",
          "auto (for meshes up to 5000 arcs), on or off: compute a lower bound for an ISP result");
ABSL_FLAG(std::string, out, "", "write the result JSON to this file");
ABSL_FLAG(std::vector<std::string>, levels, {},
          "batch: run every mesh at each of these levels (comma-separated), instead of --level");
ABSL_FLAG(std::string, out_dir, "", "batch: directory of the result files and summary.tsv");
ABSL_FLAG(int64_t, upload_above_bytes, 4 << 20,
          "remote commands: send larger meshes in chunks (UploadMesh) before the job");
ABSL_FLAG(int32_t, concurrency, 4, "batch: jobs submitted and followed at once");
ABSL_FLAG(double, patience, 600,
          "batch: give a job up after this many seconds without an answer from the server");
ABSL_FLAG(std::string, result, "", "result JSON to validate");
ABSL_FLAG(bool, progress, true, "show live progress on stderr");
ABSL_FLAG(std::string, server, "127.0.0.1:50051",
          "ispq-server to use, HOST:PORT (quantize uses it unless --local is given); several "
          "replicas as HOST:PORT,HOST:PORT or a gRPC target such as dns:///NAME:PORT");
ABSL_FLAG(std::string, health_service, "",
          "health: the health service to ask: \"\" (liveness) or readiness; exec probes use it "
          "when TLS is on");
ABSL_FLAG(std::string, lb_policy, "",
          "how calls spread over the addresses of --server: round_robin or pick_first "
          "(default: gRPC's, pick_first)");
ABSL_FLAG(bool, tls, false, "connect with TLS, verifying the server with the system's roots");
ABSL_FLAG(std::string, tls_ca, "", "PEM roots that verify the server (implies --tls)");
ABSL_FLAG(std::string, tls_cert, "", "PEM client certificate for mutual TLS (implies --tls)");
ABSL_FLAG(std::string, tls_key, "", "PEM private key of --tls_cert");
ABSL_FLAG(std::string, auth_token, "",
          "bearer token for a server started with one (default: $ISPQ_AUTH_TOKEN)");
ABSL_FLAG(double, deadline, 0, "give up a remote quantize or watch after this many seconds");
ABSL_FLAG(int64_t, from, 0, "watch: first event number to stream");
ABSL_FLAG(std::string, state, "", "jobs: only jobs in this state (QUEUED, RUNNING, SUCCEEDED...)");
ABSL_FLAG(int32_t, limit, 50, "jobs: at most this many, newest first (0: all)");

namespace {

constexpr char kUsage[] =
    "ispq: quantize T-meshes for hexahedral meshing.\n"
    "usage:\n"
    "  ispq stats FILE [--json]\n"
    "      validate a T-mesh and print its counts\n"
    "  ispq quantize FILE (--local | --server HOST:PORT) (--level P | --scaling S |\n"
    "       --target-hexes N) [--method isp|exact] [--lower-bound auto|on|off]\n"
    "       [--mixed-sign=true|false] [--time-limit SECONDS] [--out RESULT.json] [--json]\n"
    "      quantize in-process or on a server (default 127.0.0.1:50051); exit 0 only for a\n"
    "      valid result; --method exact proves optimality (or reports the gap at the limit)\n"
    "  ispq validate FILE --result RESULT.json [--level P | --scaling S]\n"
    "      check any quantization with the product's validator\n"
    "  ispq submit FILE (--level P | ...) [--json]   queue a job on the server, print its name\n"
    "  ispq watch JOB [--from N] [--out RESULT.json] [--json]\n"
    "      follow a job to its end (resuming broken streams) and show its result\n"
    "  ispq cancel JOB                               cancel a queued or running job\n"
    "  ispq jobs [--state STATE] [--limit N] [--json] list the server's jobs\n"
    "  ispq health                                   SERVING (exit 0) or not (exit 6)\n"
    "  ispq server-stats                             the server's counters as JSON\n"
    "  ispq batch DIR_OR_FILES... (--level P | --levels P,P,... | ...) --out-dir DIR\n"
    "       [--concurrency N] [--patience SECONDS]\n"
    "      quantize every T-mesh found on a server, riding out restarts; one result file per\n"
    "      job and OUT/summary.tsv; exit 0 only if every job has a valid result\n"
    "  remote commands take --server HOST:PORT[,HOST:PORT...] or dns:///NAME:PORT,\n"
    "  --lb_policy round_robin|pick_first, --tls, --tls-ca F, --tls-cert F --tls-key F,\n"
    "  --auth-token T (or $ISPQ_AUTH_TOKEN) and --deadline SECONDS\n";

// absl flags are identifiers; accept the dashed spellings users type (--time-limit).
std::vector<char*> NormalizeFlagNames(int argc, char** argv, std::vector<std::string>& storage) {
  storage.assign(argv, argv + argc);
  std::vector<char*> normalized;
  for (std::string& arg : storage) {
    if (arg.rfind("--", 0) == 0) {
      const size_t end = std::min(arg.find('='), arg.size());
      for (size_t i = 2; i < end; ++i) {
        if (arg[i] == '-') arg[i] = '_';
      }
    }
    normalized.push_back(arg.data());
  }
  return normalized;
}

// The scaling flags as a message; at most one may be given.
bool ScalingFromFlags(ispq::v1::Scaling& scaling) {
  int given = 0;
  if (absl::GetFlag(FLAGS_level) >= 0) {
    scaling.set_level_percent(absl::GetFlag(FLAGS_level));
    ++given;
  }
  if (absl::GetFlag(FLAGS_scaling) != 0) {
    scaling.set_factor(absl::GetFlag(FLAGS_scaling));
    ++given;
  }
  if (absl::GetFlag(FLAGS_target_hexes) != 0) {
    scaling.set_target_hexes(absl::GetFlag(FLAGS_target_hexes));
    ++given;
  }
  if (given > 1) std::cerr << "ispq: give only one of --level, --scaling, --target-hexes\n";
  return given <= 1;
}

// --method and --lower-bound into the message; false (with a message) for unknown values.
bool MethodFromFlags(ispq::v1::QuantizationOptions& q) {
  const std::string method = absl::GetFlag(FLAGS_method);
  if (method == "isp") {
    q.set_method(ispq::v1::METHOD_ISP);
  } else if (method == "exact") {
    q.set_method(ispq::v1::METHOD_EXACT);
  } else {
    std::cerr << "ispq: --method must be isp or exact, got '" << method << "'\n";
    return false;
  }
  const std::string bound = absl::GetFlag(FLAGS_lower_bound);
  if (bound == "on" || bound == "off") {
    q.set_lower_bound(bound == "on");
  } else if (bound != "auto") {
    std::cerr << "ispq: --lower-bound must be auto, on or off, got '" << bound << "'\n";
    return false;
  }
  return true;
}

// The quantization flags as a message, shared by quantize (both paths) and submit.
bool QuantizationFromFlags(ispq::v1::QuantizationOptions& q) {
  if (!ScalingFromFlags(*q.mutable_scaling()) || !MethodFromFlags(q)) return false;
  q.set_mixed_sign(absl::GetFlag(FLAGS_mixed_sign));
  q.set_decompose(absl::GetFlag(FLAGS_decompose));
  q.set_per_arc_nonnegative(absl::GetFlag(FLAGS_per_arc_nonnegative));
  q.set_reference_block_boxes(absl::GetFlag(FLAGS_reference_block_boxes));
  const double limit = absl::GetFlag(FLAGS_time_limit);
  if (limit < 0) {
    std::cerr << "ispq: --time-limit must be positive\n";
    return false;
  }
  if (limit > 0) {
    q.mutable_time_limit()->set_seconds(static_cast<int64_t>(limit));
    q.mutable_time_limit()->set_nanos(
        static_cast<int32_t>((limit - static_cast<double>(static_cast<int64_t>(limit))) * 1e9));
  }
  return true;
}

// Where the server is and how to reach it, with the output flags of remote commands.
ispq::cli::RemoteCommandOptions RemoteFromFlags() {
  ispq::cli::RemoteCommandOptions remote;
  remote.connection.address = absl::GetFlag(FLAGS_server);
  remote.connection.lb_policy = absl::GetFlag(FLAGS_lb_policy);
  remote.connection.tls = absl::GetFlag(FLAGS_tls);
  remote.connection.tls_ca_file = absl::GetFlag(FLAGS_tls_ca);
  remote.connection.tls_cert_file = absl::GetFlag(FLAGS_tls_cert);
  remote.connection.tls_key_file = absl::GetFlag(FLAGS_tls_key);
  remote.connection.auth_token = absl::GetFlag(FLAGS_auth_token);
  if (const char* token = std::getenv("ISPQ_AUTH_TOKEN");
      remote.connection.auth_token.empty() && token != nullptr) {
    remote.connection.auth_token = token;
  }
  const double deadline = absl::GetFlag(FLAGS_deadline);
  if (deadline > 0) remote.deadline = absl::Seconds(deadline);
  remote.json = absl::GetFlag(FLAGS_json);
  remote.progress = absl::GetFlag(FLAGS_progress);
  remote.out_path = absl::GetFlag(FLAGS_out);
  remote.upload_above_bytes = absl::GetFlag(FLAGS_upload_above_bytes);
  return remote;
}

int RunQuantize(const std::vector<char*>& args) {
  if (args.size() != 3) {
    std::cerr << "usage: ispq quantize FILE (--local | --server HOST:PORT) (--level P | "
                 "--scaling S) [...]\n";
    return ispq::cli::kExitUsage;
  }
  ispq::cli::QuantizeCommandOptions options;
  options.mesh_path = args[2];
  if (!QuantizationFromFlags(options.quantization)) return ispq::cli::kExitUsage;
  options.out_path = absl::GetFlag(FLAGS_out);
  options.json = absl::GetFlag(FLAGS_json);
  options.progress = absl::GetFlag(FLAGS_progress);
  if (absl::GetFlag(FLAGS_local)) return ispq::cli::RunLocalQuantize(options);
  return ispq::cli::RunRemoteQuantize(options, RemoteFromFlags());
}

// `ispq batch`: the quantization flags once per --levels entry (or once).
int RunBatchCommand(const std::vector<char*>& args, const ispq::cli::RemoteCommandOptions& remote) {
  ispq::cli::BatchCommandOptions batch;
  batch.inputs.assign(args.begin() + 2, args.end());
  batch.out_dir = absl::GetFlag(FLAGS_out_dir);
  batch.concurrency = absl::GetFlag(FLAGS_concurrency);
  batch.patience = absl::Seconds(absl::GetFlag(FLAGS_patience));
  if (batch.inputs.empty() || batch.out_dir.empty() || batch.concurrency < 1) {
    std::cerr << "usage: ispq batch DIR_OR_FILES... (--level P | --levels P,P,... | --scaling S | "
                 "--target-hexes N) --out-dir DIR [--concurrency N >= 1] [--server ...]\n";
    return ispq::cli::kExitUsage;
  }
  ispq::v1::QuantizationOptions quantization;
  if (!QuantizationFromFlags(quantization)) return ispq::cli::kExitUsage;
  const std::vector<std::string> levels = absl::GetFlag(FLAGS_levels);
  if (levels.empty()) batch.variants.push_back(quantization);
  for (const std::string& level : levels) {
    int percent = 0;
    if (quantization.scaling().kind_case() != ispq::v1::Scaling::KIND_NOT_SET ||
        !absl::SimpleAtoi(level, &percent)) {
      std::cerr << "ispq: --levels takes levels in percent (e.g. 0,25,100) instead of --level, "
                   "--scaling or --target-hexes, got '"
                << level << "'\n";
      return ispq::cli::kExitUsage;
    }
    batch.variants.push_back(quantization);
    batch.variants.back().mutable_scaling()->set_level_percent(percent);
  }
  return ispq::cli::RunBatch(batch, remote);
}

// submit, watch, cancel, jobs, health, server-stats, batch; -1 for another command.
int RunServerCommand(const std::string& command, const std::vector<char*>& args) {
  const ispq::cli::RemoteCommandOptions remote = RemoteFromFlags();
  const auto usage = [](const char* text) {
    std::cerr << "usage: ispq " << text << "\n";
    return ispq::cli::kExitUsage;
  };
  if (command == "submit") {
    if (args.size() != 3) return usage("submit FILE (--level P | --scaling S) [--server ...]");
    ispq::v1::QuantizationOptions quantization;
    if (!QuantizationFromFlags(quantization)) return ispq::cli::kExitUsage;
    return ispq::cli::RunSubmit(args[2], quantization, remote);
  }
  if (command == "batch") return RunBatchCommand(args, remote);
  if (command == "watch") {
    if (args.size() != 3) return usage("watch JOB [--from N] [--out RESULT.json] [--json]");
    return ispq::cli::RunWatch(args[2], absl::GetFlag(FLAGS_from), remote);
  }
  if (command == "cancel") {
    if (args.size() != 3) return usage("cancel JOB");
    return ispq::cli::RunCancel(args[2], remote);
  }
  if (command == "jobs") {
    if (args.size() != 2) return usage("jobs [--state STATE] [--limit N] [--json]");
    ispq::v1::JobState state = ispq::v1::JOB_STATE_UNSPECIFIED;
    const std::string state_name = absl::GetFlag(FLAGS_state);
    if (!state_name.empty() && !ispq::v1::JobState_Parse(state_name, &state)) {
      return usage("jobs --state (QUEUED | RUNNING | SUCCEEDED | FAILED | CANCELLED)");
    }
    return ispq::cli::RunListJobs(state, absl::GetFlag(FLAGS_limit), remote);
  }
  if (command == "health") {
    if (args.size() != 2) return usage("health [--server HOST:PORT] [--health_service S]");
    return ispq::cli::RunHealth(remote, absl::GetFlag(FLAGS_health_service));
  }
  if (command == "server-stats") {
    if (args.size() != 2) return usage("server-stats [--server HOST:PORT]");
    return ispq::cli::RunServerStats(remote);
  }
  return -1;
}

int RunValidate(const std::vector<char*>& args) {
  if (args.size() != 3 || absl::GetFlag(FLAGS_result).empty()) {
    std::cerr << "usage: ispq validate FILE --result RESULT.json [--level P | --scaling S]\n";
    return ispq::cli::kExitUsage;
  }
  ispq::cli::ValidateCommandOptions options;
  options.mesh_path = args[2];
  options.result_path = absl::GetFlag(FLAGS_result);
  if (!ScalingFromFlags(options.scaling)) return ispq::cli::kExitUsage;
  if (options.scaling.kind_case() == ispq::v1::Scaling::KIND_NOT_SET) {
    options.scaling.set_factor(1.0);  // validity does not depend on s; only the objective does
  }
  options.reference_block_boxes = absl::GetFlag(FLAGS_reference_block_boxes);
  options.json = absl::GetFlag(FLAGS_json);
  return ispq::cli::RunValidate(options);
}

}  // namespace

int main(int argc, char** argv) {
  ispq::MapLargeAllocationsSeparately();
  absl::SetProgramUsageMessage(kUsage);
  std::vector<std::string> storage;
  std::vector<char*> normalized = NormalizeFlagNames(argc, argv, storage);
  const std::vector<char*> args =
      absl::ParseCommandLine(static_cast<int>(normalized.size()), normalized.data());
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
  if (command == "quantize") return RunQuantize(args);
  if (command == "validate") return RunValidate(args);
  if (const int exit_code = RunServerCommand(command, args); exit_code >= 0) return exit_code;
  std::cerr << "ispq: unknown command '" << command << "'\n" << kUsage;
  return ispq::cli::kExitUsage;
}
