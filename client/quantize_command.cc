// SPDX-License-Identifier: Apache-2.0
#include "client/quantize_command.h"

#include <iostream>

#include "client/announced_upload.h"
#include "client/exit_codes.h"
#include "client/job_output.h"
#include "client/progress_printer.h"
#include "client/quantize_input.h"
#include "client/quantizer_client.h"
#include "client/result_output.h"
#include "core/proto/quantization_proto.h"
#include "core/quantizer.h"

namespace ispq::cli {
namespace {

// Forwards the algorithm's progress events to the terminal printer.
class PrintingObserver : public ProgressObserver {
 public:
  explicit PrintingObserver(ProgressPrinter& printer) : printer_(printer) {}
  void OnProgress(const ProgressEvent& event) override { printer_.Update(ProgressToProto(event)); }

 private:
  ProgressPrinter& printer_;
};

}  // namespace

int RunLocalQuantize(const QuantizeCommandOptions& options) {
  QuantizeInputOrExit loaded =
      LoadQuantizeInput(options.mesh_path, options.quantization, MeshUse::kSolveHere);
  if (!loaded.input.has_value()) return loaded.exit_code;
  const TMesh& mesh = loaded.input->mesh;
  const QuantizeOptions& quantize_options = loaded.input->options;
  ProgressPrinter printer(stderr);
  PrintingObserver observer(printer);
  absl::StatusOr<QuantizeResult> result =
      Quantize(mesh, quantize_options, options.progress ? &observer : nullptr);
  printer.Finish();
  if (!result.ok()) {
    std::cerr << "ispq: quantization failed: " << result.status().message() << "\n";
    return kExitFailed;
  }
  return OutputResult(QuantizationResultToProto(*result, quantize_options.scaling, mesh),
                      options.out_path, options.json);
}

int RunRemoteQuantize(const QuantizeCommandOptions& options, const RemoteCommandOptions& server) {
  QuantizeInputOrExit loaded =
      LoadQuantizeInput(options.mesh_path, options.quantization, MeshUse::kSendToServer);
  if (!loaded.input.has_value()) return loaded.exit_code;
  v1::QuantizeRequest& request = MakeQuantizeRequest(*loaded.input, options.quantization);
  RemoteCommandOptions output = server;
  output.json = options.json;
  output.progress = options.progress;
  output.out_path = options.out_path;
  absl::StatusOr<client::QuantizerClient> client =
      client::QuantizerClient::Connect(server.connection);
  if (!client.ok()) return ReportError(server.connection.address, client.status());
  absl::StatusOr<std::string> uploaded =
      UploadIfLarge(*client, request, server.upload_above_bytes, options.progress);
  if (!uploaded.ok()) return ReportError(server.connection.address, uploaded.status());
  JobEventPrinter printer(options.progress);
  client::StreamOptions stream;
  stream.timeout = server.deadline;
  stream.on_event = [&printer](const v1::QuantizeEvent& event) { return printer.OnEvent(event); };
  const client::JobOutcome outcome = client->Quantize(request, stream);
  printer.Finish();
  if (!uploaded->empty()) (void)client->DeleteMesh(*uploaded);  // the job is over
  return ReportJobOutcome(outcome, output);
}

}  // namespace ispq::cli
