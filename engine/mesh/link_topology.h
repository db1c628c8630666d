// The links that decide whether a region's boundary is a closed 3-manifold at a simplex: at a
// boundary vertex, the boundary triangles opposite it must form a 2-sphere; at a boundary edge,
// the boundary edges opposite it a circle. Shared by the certificate (mesh side) and the refiner,
// which refines where a link fails.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace mesh4d::mesh {

/// Each triangle's vertices sorted. Each edge in exactly two triangles, connected through shared
/// edges, Euler characteristic 2.
bool link_is_sphere(const std::vector<std::array<std::uint32_t, 3>>& triangles);
/// Each edge's ends sorted. Every vertex in exactly two edges, and connected.
bool link_is_circle(const std::vector<std::array<std::uint32_t, 2>>& edges);

}  // namespace mesh4d::mesh
