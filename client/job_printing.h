// How the client shows jobs and progress: one line per job, a live line on a terminal, plain
// lines otherwise.
#pragma once

#include <iosfwd>

#include "mesh4d/v1/mesh4d.pb.h"

namespace mesh4d::client {

/// "ID  STATE  name  progress or error".
void print_job_line(std::ostream& out, const v1::Job& job);
/// The quality table of a finished job.
void print_stats(std::ostream& out, const v1::MeshStats& stats);
/// One progress report; `live` rewrites the current terminal line instead of adding one.
void print_progress(std::ostream& out, const v1::Progress& p, bool live);

}  // namespace mesh4d::client
