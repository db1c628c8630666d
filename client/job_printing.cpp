#include "job_printing.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <cstdio>
#include <ostream>
#include <string>

namespace mesh4d::client {
namespace {

std::string state_name(v1::JobState s) {
  std::string name = v1::JobState_Name(s);
  return name.substr(name.find_last_of('_') + 1);
}

std::string phase_name(v1::Phase p) {
  std::string name = v1::Phase_Name(p);
  return name.substr(6);  // after "PHASE_"
}

}  // namespace

void print_job_line(std::ostream& out, const v1::Job& job) {
  out << job.id() << "  " << state_name(job.state());
  if (!job.name().empty()) out << "  " << job.name();
  if (job.state() == v1::JOB_STATE_QUEUED) out << "  position " << job.queue_position();
  if (job.has_progress() && job.state() == v1::JOB_STATE_RUNNING)
    out << "  " << phase_name(job.progress().phase()) << " " << job.progress().vertices()
        << " vertices";
  if (job.state() == v1::JOB_STATE_SUCCEEDED)
    out << "  " << job.stats().pentatopes() << " pentatopes";
  if (!job.error().empty()) out << "  " << job.error();
  out << "\n";
}

void print_stats(std::ostream& out, const v1::MeshStats& s) {
  char line[256];
  auto row = [&](const char* name, const v1::Distribution& d) {
    std::snprintf(line, sizeof line, "  %-18s min %.4f  max %.4f  mean %.4f  std %.4f\n", name,
                  d.min(), d.max(), d.mean(), d.stddev());
    out << line;
  };
  std::snprintf(line, sizeof line,
                "  vertices %llu, pentatopes %llu, boundary tetrahedra %llu, shortest edge %.4g\n",
                (unsigned long long)s.vertices(), (unsigned long long)s.pentatopes(),
                (unsigned long long)s.boundary_tetrahedra(), s.shortest_edge());
  out << line;
  row("radius-edge ratio", s.radius_edge_ratio());
  row("normalized volume", s.normalized_volume());
  const auto& i = s.insertions();
  std::snprintf(line, sizeof line,
                "  insertions R1..R5 %llu %llu %llu %llu %llu, removals %llu, %.2f s\n",
                (unsigned long long)i.r1(), (unsigned long long)i.r2(), (unsigned long long)i.r3(),
                (unsigned long long)i.r4(), (unsigned long long)i.r5(),
                (unsigned long long)s.removals().r5(), s.elapsed_seconds());
  out << line;
  std::snprintf(line, sizeof line,
                "  boundary vertices off the surface by at most %.3g (sag offset)\n",
                s.boundary_offset());
  out << line;
  for (const v1::LabelCertificate& c : s.certificate()) {
    std::snprintf(
        line, sizeof line,
        "  label %u: %llu pieces (%llu touching) / image %llu (face-connected %llu); "
        "non-manifold vertices "
        "%llu, edges %llu, triangles %llu; 4-volume %.4g of %.4g; worst frame %+.1f %% "
        "at t = %g\n",
        c.label(), (unsigned long long)c.mesh_pieces(), (unsigned long long)c.touching_pieces(),
        (unsigned long long)c.image_pieces(), (unsigned long long)c.image_face_pieces(),
        (unsigned long long)c.non_manifold_vertices(), (unsigned long long)c.non_manifold_edges(),
        (unsigned long long)c.non_manifold_triangles(), c.volume(), c.voxel_volume(),
        100 * c.worst_frame_volume_error(), c.worst_frame_time());
    out << line;
    std::snprintf(line, sizeof line,
                  "    boundary distance, mesh to image: max %.3g, mean %.3g; image to mesh: max "
                  "%.3g, mean %.3g (%llu samples a side)\n",
                  c.mesh_to_image_max(), c.mesh_to_image_mean(), c.image_to_mesh_max(),
                  c.image_to_mesh_mean(), (unsigned long long)c.distance_samples());
    out << line;
  }
}

void print_progress(std::ostream& out, const v1::Progress& p, bool live) {
  char line[256];
  const auto& i = p.insertions();
  std::snprintf(line, sizeof line,
                "%-10s %8llu vertices %9llu pentatopes  R1 %llu R2 %llu R3 %llu R4 %llu R5 %llu"
                "  rollbacks %llu  %.1f s",
                phase_name(p.phase()).c_str(), (unsigned long long)p.vertices(),
                (unsigned long long)p.pentatopes(), (unsigned long long)i.r1(),
                (unsigned long long)i.r2(), (unsigned long long)i.r3(), (unsigned long long)i.r4(),
                (unsigned long long)i.r5(), (unsigned long long)p.rollbacks(), p.elapsed_seconds());
  if (live) {
    // A line longer than the terminal would wrap, and "\r" would then rewrite only its tail.
    winsize size{};
    std::string text = line;
    if (ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 1 &&
        text.size() >= size.ws_col)
      text.resize(size.ws_col - 1u);
    out << "\r" << text << "\x1b[K" << std::flush;
  } else
    out << line << "\n";
}

}  // namespace mesh4d::client
