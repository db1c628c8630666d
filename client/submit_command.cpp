// submit: reads a 4D label image (or a series of 3D frames) with the engine's ITK reader,
// uploads it as raw labels with its header and SHA-256, prints the job id; with --wait, follows
// the job and downloads the mesh.
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <optional>
#include <random>

#include "connection.h"
#include "domain/image_io.h"
#include "exit_codes.h"
#include "job_calls.h"
#include "job_commands.h"
#include "job_printing.h"
#include "wire/params_json.h"
#include "wire/submit_stream.h"
#include "wire/upload_codec.h"

namespace mesh4d::client {
namespace {

struct SubmitOptions {
  std::string image;
  std::vector<std::string> frames;
  std::string params_file;
  double delta = 0, rho = 0, time_scale = 0;
  std::string time_topology;
  std::string sag_offset;
  unsigned threads = 0;
  unsigned extend_time = 0;
  std::optional<unsigned> min_island_voxels;
  std::string name, request_id, out;
  bool wait = false;
  bool strict = false;
};

// --params file (JSON keys as the RefineParams fields, read as the REST face reads them), then
// the flags on top.
void fill_params(const SubmitOptions& o, v1::RefineParams* p) {
  if (!o.params_file.empty()) {
    std::ifstream in(o.params_file);
    if (!in) throw std::runtime_error("cannot read " + o.params_file);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    try {
      wire::parse_params(text, p);
    } catch (const std::exception& e) {
      throw std::runtime_error(o.params_file + ": " + e.what());
    }
  }
  if (o.delta) p->set_delta(o.delta);
  if (o.rho) p->set_radius_edge_bound(o.rho);
  if (o.threads) p->set_threads(o.threads);
  if (o.extend_time) p->set_extend_time_frames(o.extend_time);
  if (o.time_scale) p->set_time_scale(o.time_scale);
  if (o.time_topology == "periodic") p->set_time_topology(v1::TIME_TOPOLOGY_PERIODIC);
  if (o.time_topology == "open") p->set_time_topology(v1::TIME_TOPOLOGY_OPEN);
  if (!o.sag_offset.empty()) p->set_sag_offset(o.sag_offset == "on");
  if (o.strict) p->set_strict(true);
  if (o.min_island_voxels) p->set_min_island_voxels(*o.min_island_voxels);
}

std::string random_request_id() {
  std::mt19937_64 rng{std::random_device{}()};
  char id[40];
  std::snprintf(id, sizeof id, "cli-%016llx%016llx", (unsigned long long)rng(),
                (unsigned long long)rng());
  return id;
}

int run_submit(const GlobalOptions& global, const SubmitOptions& o) {
  v1::JobSpec spec;
  std::string raw;
  try {
    // Frames of a series are one frame apart; the mesh's time scale is a parameter.
    const domain::LabelImage4 image = o.frames.empty() ? domain::read_label_image(o.image)
                                                       : domain::read_label_frames(o.frames, 1);
    raw = wire::encode_upload(image, spec.mutable_image());
    fill_params(o, spec.mutable_params());
  } catch (const std::exception& e) {
    std::cerr << "mesh4d-client: submit: " << e.what() << "\n";
    return kExitLocal;
  }
  spec.set_name(o.name.empty() ? (o.frames.empty() ? o.image : o.frames.front()) : o.name);
  // A request id makes a retried upload land on the same job.
  spec.set_request_id(o.request_id.empty() ? random_request_id() : o.request_id);

  auto stub = v1::MeshService::NewStub(open_channel(global));
  grpc::ClientContext context;
  prepare(context, global, false);
  v1::SubmitJobResponse response;
  const grpc::Status status = wire::submit_job(*stub, context, spec, raw, &response);
  if (!status.ok()) return report_rpc_error("submit", status, global);
  std::cout << response.job().id() << "\n" << std::flush;
  std::cerr << "time scale: " << response.job().params().time_scale() << " per frame"
            << (spec.params().time_scale() == 0 ? " (chosen from the data)" : "")
            << (response.job().params().time_topology() == v1::TIME_TOPOLOGY_PERIODIC
                    ? ", periodic time"
                    : "")
            << "\n";
  for (const auto& w : response.job().warnings()) std::cerr << "warning: " << w << "\n";
  if (!o.wait) return kExitOk;

  v1::Job final;
  const int watched = watch_job(global, response.job().id(), &final);
  if (watched != kExitOk) return watched;
  print_stats(std::cerr, final.stats());
  if (o.out.empty()) return kExitOk;
  return fetch_result(global, response.job().id(), o.out);
}

}  // namespace

void setup_submit_command(CLI::App& app, const GlobalOptions& global, int* exit_code) {
  auto o = std::make_shared<SubmitOptions>();
  CLI::App* cmd = app.add_subcommand(
      "submit", "upload a 4D label image (NIfTI, MetaImage, NRRD) and print the job id");
  cmd->add_option("IMAGE", o->image, "a 4D label image")->check(CLI::ExistingFile);
  cmd->add_option("--frames", o->frames, "3D label files, one per frame, instead of IMAGE")
      ->check(CLI::ExistingFile);
  cmd->add_option("--params", o->params_file, "JSON file of refinement parameters")
      ->check(CLI::ExistingFile);
  cmd->add_option("--delta", o->delta, "surface sampling distance Δ (physical units)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--rho", o->rho, "radius-edge bound ρ̄")->check(CLI::PositiveNumber);
  cmd->add_option("--threads", o->threads,
                  "worker threads for this job, capped by the server (default: its share of the "
                  "server's cores)");
  cmd->add_option("--extend-time", o->extend_time,
                  "repeat the first and last frames N times before meshing: the mesh spans N "
                  "more frames at each end")
      ->check(CLI::Range(0u, 64u));
  cmd->add_option("--min-island-voxels", o->min_island_voxels,
                  "cleanup: pieces of a label (and pockets of background) smaller than this "
                  "many voxels take their neighbors' label; 0: none (default 81)");
  cmd->add_option("--time-scale", o->time_scale,
                  "the length of one frame along t, in the image's spatial unit (default: "
                  "chosen from the data, the larger of delta and the boundary's motion per frame)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--time-topology", o->time_topology,
                  "open (default: the mesh spans the frames, flat caps at its ends) or periodic (a "
                  "cycle: the frame after the last is the first, the mesh closed in time)")
      ->check(CLI::IsMember({"open", "periodic"}));
  cmd->add_option("--sag-offset", o->sag_offset,
                  "on (default: boundary vertices move off the surface for their facets' sag, so "
                  "that regions keep their volume) or off (every boundary vertex on the surface)")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--name", o->name, "a name shown in listings (default: the file)");
  cmd->add_option("--request-id", o->request_id, "idempotency key (default: random)");
  cmd->add_flag("--wait", o->wait, "follow the job to its end (progress on stderr)");
  cmd->add_flag("--strict", o->strict,
                "fail the job when its fidelity certificate finds a defect (else a warning)");
  cmd->add_option("--out", o->out, "with --wait: write the mesh (.m4d) here");
  cmd->callback([&global, o, exit_code, cmd] {
    if (o->image.empty() == o->frames.empty())
      throw CLI::ValidationError("submit", "give either IMAGE or --frames, not both or neither");
    if (!o->out.empty() && !o->wait)
      throw CLI::ValidationError("--out", "--out needs --wait (or use 'fetch ID --out FILE')");
    (void)cmd;
    *exit_code = run_submit(global, *o);
  });
}

}  // namespace mesh4d::client
