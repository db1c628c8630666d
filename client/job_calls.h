// Calls shared by several subcommands: following a job to its end, downloading its mesh.
#pragma once

#include <string>

#include "connection.h"
#include "mesh4d/v1/mesh4d.grpc.pb.h"

namespace mesh4d::client {

/// Streams the job's events to stderr (a live line on a terminal) until it ends; `final` gets
/// the job as it ended. Returns an exit code: kExitOk once SUCCEEDED.
int watch_job(const GlobalOptions& global, const std::string& id, v1::Job* final);

/// Downloads the mesh of a SUCCEEDED job to `path` (checked against the header's size and
/// SHA-256, written to a temporary file then renamed). Returns an exit code.
int fetch_result(const GlobalOptions& global, const std::string& id, const std::string& path);

}  // namespace mesh4d::client
