// stats: the quality table of a .m4d mesh (the paper's Table 2 columns) and each label's
// topology (mesh/topology_certificate.h: pieces, non-manifold boundary simplices, 4-volume),
// measured from the file itself, as text or, with --json, as one JSON object.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "exit_codes.h"
#include "mesh/mesh_io.h"
#include "mesh/mesh_stats.h"
#include "mesh/topology_certificate.h"
#include "mesh_file_commands.h"

namespace mesh4d::client {
namespace {

nlohmann::json distribution(const mesh::Distribution& d) {
  return {{"min", d.min}, {"max", d.max}, {"mean", d.mean}, {"stddev", d.stddev}};
}

void print_json(const mesh::MeshStats& s, const mesh::TopologyCertificate& topology) {
  nlohmann::json j;
  j["vertices"] = s.vertices;
  j["pentatopes"] = s.pentatopes;
  j["boundary_tetrahedra"] = s.boundary_tetrahedra;
  j["shortest_edge"] = s.shortest_edge;
  j["radius_edge_ratio"] = distribution(s.radius_edge_ratio);
  j["normalized_volume"] = distribution(s.normalized_volume);
  j["normalized_volume_histogram"] = s.normalized_volume_histogram;
  for (const mesh::LabelTopology& l : topology.labels)
    j["labels"].push_back({{"label", l.label},
                           {"pentatopes", l.pentatopes},
                           {"volume", l.volume},
                           {"pieces", l.components},
                           {"touching_pieces", l.touching_components},
                           {"non_manifold_vertices", l.non_manifold_vertices},
                           {"non_manifold_edges", l.non_manifold_edges},
                           {"non_manifold_triangles", l.non_manifold_triangles},
                           {"boundary_list_mismatches", l.boundary_list_mismatches}});
  j["manifold"] = topology.manifold();
  std::cout << j.dump(2) << "\n";
}

void print_table(const mesh::MeshStats& s, const mesh::TopologyCertificate& topology) {
  std::printf(
      "vertices             %llu\npentatopes           %llu\n"
      "boundary tetrahedra  %llu\nshortest edge        %.6g\n",
      (unsigned long long)s.vertices, (unsigned long long)s.pentatopes,
      (unsigned long long)s.boundary_tetrahedra, s.shortest_edge);
  std::printf("%-20s %10s %10s %10s %10s\n", "", "min", "max", "mean", "std");
  for (const auto& [name, d] : {std::pair{"radius-edge ratio", s.radius_edge_ratio},
                                std::pair{"normalized volume", s.normalized_volume}})
    std::printf("%-20s %10.4f %10.4f %10.4f %10.4f\n", name, d.min, d.max, d.mean, d.stddev);
  std::printf("normalized volume histogram (%zu bins over [0, 1]):\n",
              s.normalized_volume_histogram.size());
  const std::size_t bins = s.normalized_volume_histogram.size();
  for (std::size_t i = 0; i < bins; ++i)
    if (s.normalized_volume_histogram[i])
      std::printf("  [%.2f, %.2f%c %llu\n", double(i) / bins, double(i + 1) / bins,
                  i + 1 == bins ? ']' : ')', (unsigned long long)s.normalized_volume_histogram[i]);
  for (const mesh::LabelTopology& l : topology.labels)
    std::printf(
        "label %-5u %llu pentatopes, 4D volume %.6g, %zu pieces (%zu touching another), "
        "non-manifold boundary vertices %zu, edges %zu, triangles %zu\n",
        unsigned(l.label), (unsigned long long)l.pentatopes, l.volume, l.components,
        l.touching_components, l.non_manifold_vertices, l.non_manifold_edges,
        l.non_manifold_triangles);
}

int run_stats(const std::string& path, bool json) {
  try {
    const mesh::Mesh4 m = mesh::read_m4d(path);
    const mesh::MeshStats s = mesh::compute_stats(m);
    const mesh::TopologyCertificate topology = mesh::certify_topology(m);
    if (json)
      print_json(s, topology);
    else
      print_table(s, topology);
  } catch (const std::exception& e) {
    std::cerr << "mesh4d-client: stats: " << e.what() << "\n";
    return kExitLocal;
  }
  return kExitOk;
}

}  // namespace

void setup_stats_command(CLI::App& app, int* exit_code) {
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand("stats", "print the quality table of a .m4d mesh");
  cmd->add_option("MESH", *path, ".m4d mesh")->required()->check(CLI::ExistingFile);
  cmd->add_flag("--json", *json, "one JSON object instead of the table");
  cmd->callback([path, json, exit_code] { *exit_code = run_stats(*path, *json); });
}

}  // namespace mesh4d::client
