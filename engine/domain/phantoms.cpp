#include "domain/phantoms.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

namespace mesh4d::domain {
namespace {

// Fills the image with label(p) at every voxel center p.
LabelImage4 voxelize(const Dims4& dims, const Vec4& spacing,
                     const std::function<Label(const Point4&)>& label) {
  LabelImage4 image(dims, spacing);
  for (std::size_t t = 0; t < dims[3]; ++t)
    for (std::size_t z = 0; z < dims[2]; ++z)
      for (std::size_t y = 0; y < dims[1]; ++y)
        for (std::size_t x = 0; x < dims[0]; ++x) {
          const Label l = label(image.voxel_center(x, y, z, t));
          if (l != 0) image.set(x, y, z, t, l);
        }
  return image;
}

Point4 center_of(const Dims4& dims, const Vec4& spacing) {
  Point4 c;
  for (int a = 0; a < 4; ++a) c[a] = 0.5 * double(dims[a] - 1) * spacing[a];
  return c;
}

}  // namespace

LabelImage4 hypersphere_phantom(const Dims4& dims, const Vec4& spacing, double radius) {
  const Point4 c = center_of(dims, spacing);
  return voxelize(dims, spacing, [&](const Point4& p) -> Label {
    double r2 = 0;
    for (int a = 0; a < 4; ++a) r2 += (p[a] - c[a]) * (p[a] - c[a]);
    return r2 < radius * radius ? 1 : 0;
  });
}

LabelImage4 hypertorus_phantom(const Dims4& dims, const Vec4& spacing, double major_radius,
                               double minor_radius) {
  const Point4 c = center_of(dims, spacing);
  return voxelize(dims, spacing, [&](const Point4& p) -> Label {
    const double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2], dt = p[3] - c[3];
    const double ring = std::sqrt(dx * dx + dy * dy) - major_radius;
    return ring * ring + dz * dz + dt * dt < minor_radius * minor_radius ? 1 : 0;
  });
}

LabelImage4 beating_ventricle_phantom(const Dims4& dims, const Vec4& spacing) {
  const Point4 c = center_of(dims, spacing);
  const double frames = double(dims[3]);
  return voxelize(dims, spacing, [&](const Point4& p) -> Label {
    const double frame = (p[3] - 0.0) / spacing[3];
    // Contraction: 0 at end-diastole (frame 0), 1 at end-systole (mid-cycle).
    const double phase = 0.5 * (1 - std::cos(2 * std::numbers::pi * frame / frames));
    const double cavity_r = 25.0 * (1 - phase / 3);  // in-plane radius, mm
    const double cavity_a = 70.0 * (1 - phase / 6);  // half long axis, mm
    const double wall = 8.0 + 4.0 * phase;           // mm
    const double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
    auto inside = [&](double r, double a) {
      return (dx * dx + dy * dy) / (r * r) + dz * dz / (a * a) < 1;
    };
    if (inside(cavity_r, cavity_a)) return 1;
    if (inside(cavity_r + wall, cavity_a + wall)) return 2;
    return 0;
  });
}

LabelImage4 merging_blobs_phantom(const Dims4& dims, const Vec4& spacing) {
  const Point4 c = center_of(dims, spacing);
  const double extent_t = double(dims[3] - 1) * spacing[3];
  const double radius = 0.22 * double(dims[1]) * spacing[1];
  return voxelize(dims, spacing, [&](const Point4& p) -> Label {
    // Half distance between the centers: 1.6 radii at both ends of time, 0.4 at mid-time.
    const double s = std::sin(std::numbers::pi * p[3] / extent_t);
    const double half = radius * (1.6 - 1.2 * s);
    const double dy = p[1] - c[1], dz = p[2] - c[2];
    const double d1 = (p[0] - c[0] + half), d2 = (p[0] - c[0] - half);
    const double r2 = radius * radius;
    return (d1 * d1 + dy * dy + dz * dz < r2 || d2 * d2 + dy * dy + dz * dz < r2) ? 1 : 0;
  });
}

LabelImage4 thin_wall_phantom(const Dims4& dims, const Vec4& spacing) {
  const Point4 c = center_of(dims, spacing);
  const double r = 8 * spacing[0], wall = spacing[0];
  return voxelize(dims, spacing, [&](const Point4& p) -> Label {
    double r2 = 0;
    for (int a = 0; a < 4; ++a) r2 += (p[a] - c[a]) * (p[a] - c[a]);
    return r2 < r * r ? 1 : r2 < (r + wall) * (r + wall) ? 2 : 0;
  });
}

LabelImage4 checkerboard_phantom(const Dims4& dims, const Vec4& spacing) {
  // Voxel x: [3, 10) one block, [12, 19) the other; x = 10 and 11 alternate so that a voxel of
  // layer 10 has label 1 where y + z + t is even and one of layer 11 where it is odd.
  LabelImage4 image(dims, spacing);
  for (std::size_t t = 3; t + 3 < dims[3]; ++t)
    for (std::size_t z = 3; z + 3 < dims[2]; ++z)
      for (std::size_t y = 3; y + 3 < dims[1]; ++y)
        for (std::size_t x = 3; x < 19 && x + 3 < dims[0]; ++x) {
          const bool even = (y + z + t) % 2 == 0;
          if (x < 10 || x >= 12 || (x == 10 && even) || (x == 11 && !even))
            image.set(x, y, z, t, 1);
        }
  return image;
}

LabelImage4 corner_contact_phantom(const Dims4& dims, const Vec4& spacing) {
  LabelImage4 image(dims, spacing);
  const std::size_t m = dims[0] / 2;
  for (std::size_t t = 2; t + 2 < dims[3]; ++t)
    for (std::size_t z = 2; z + 2 < dims[2]; ++z)
      for (std::size_t y = 2; y + 2 < dims[1]; ++y)
        for (std::size_t x = 2; x + 2 < dims[0]; ++x) {
          const bool low = x < m && y < m && z < m && t < m;
          const bool high = x >= m && y >= m && z >= m && t >= m;
          if (low) image.set(x, y, z, t, 1);
          if (high) image.set(x, y, z, t, 2);
        }
  return image;
}

LabelImage4 island_phantom(const Dims4& dims, const Vec4& spacing) {
  LabelImage4 image = hypersphere_phantom(dims, spacing, 8 * spacing[0]);
  image.set(2, 2, 2, 2, 1);
  image.set(dims[0] / 2, dims[1] / 2, dims[2] / 2, dims[3] / 2, 0);
  return image;
}

LabelImage4 thin_plate_phantom(const Dims4& dims, const Vec4& spacing) {
  LabelImage4 image(dims, spacing);
  const double c[4] = {10, 12, 12, 12};
  for (std::size_t t = 0; t < dims[3]; ++t)
    for (std::size_t z = 0; z < dims[2]; ++z)
      for (std::size_t y = 0; y < dims[1]; ++y)
        for (std::size_t x = 0; x < dims[0]; ++x) {
          const double p[4] = {double(x), double(y), double(z), double(t)};
          double r2 = 0;
          for (int a = 0; a < 4; ++a) r2 += (p[a] - c[a]) * (p[a] - c[a]);
          const bool plate = x == 19 && y >= 7 && y < 17 && z >= 7 && z < 17 && t >= 9 && t < 15;
          if (r2 < 36 || plate) image.set(x, y, z, t, 1);
        }
  return image;
}

LabelImage4 moving_junction_phantom(const Dims4& dims, const Vec4& spacing) {
  const Point4 c = center_of(dims, spacing);
  const double r = 9 * spacing[0];
  const double extent_t = std::max(double(dims[3] - 1) * spacing[3], 1e-9);
  return voxelize(dims, spacing, [&](const Point4& p) -> Label {
    const double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
    if (dx * dx + dy * dy + dz * dz >= r * r) return 0;
    const double turn = 2 * std::numbers::pi / 3 * p[3] / extent_t;
    double angle = std::atan2(dy, dx) - turn;
    angle -= 2 * std::numbers::pi * std::floor(angle / (2 * std::numbers::pi));
    return static_cast<Label>(1 + static_cast<int>(angle / (2 * std::numbers::pi / 3)) % 3);
  });
}

LabelImage4 diagonal_island_phantom(const Dims4& dims, const Vec4& spacing) {
  LabelImage4 image(dims, spacing);
  for (std::size_t t = 2; t + 2 < dims[3]; ++t)
    for (std::size_t z = 2; z + 2 < dims[2]; ++z)
      for (std::size_t y = 2; y + 2 < dims[1]; ++y)
        for (std::size_t x = 2; x + 2 < dims[0]; ++x) {
          const bool wall = x >= 13 && y >= 12 && z >= 12;
          // Its corner voxel (12, 11, 11, t) meets the wall's (13, 12, 12, t) across a block
          // of eight voxels of which six are label 1.
          const bool island =
              x >= 9 && x <= 12 && y >= 8 && y <= 11 && z >= 8 && z <= 11 && t >= 4 && t <= 19;
          image.set(x, y, z, t, wall || island ? 2 : 1);
        }
  return image;
}

LabelImage4 thin_bridge_phantom(const Dims4& dims, const Vec4& spacing) {
  LabelImage4 image(dims, spacing);
  for (std::size_t t = 0; t < dims[3]; ++t)
    for (std::size_t z = 0; z < dims[2]; ++z)
      for (std::size_t y = 0; y < dims[1]; ++y)
        for (std::size_t x = 0; x < dims[0]; ++x) {
          const double p[4] = {double(x), double(y), double(z), double(t)};
          const double big[4] = {8, 12, 12, 12}, small[4] = {18, 12, 12, 12};
          double r2_big = 0, r2_small = 0;
          for (int a = 0; a < 4; ++a)
            r2_big += (p[a] - big[a]) * (p[a] - big[a]),
                r2_small += (p[a] - small[a]) * (p[a] - small[a]);
          const bool bar = x >= 8 && x <= 18 && y == 12 && z == 12 && t >= 10 && t < 14;
          if (r2_big < 36 || r2_small < 9 || bar) image.set(x, y, z, t, 1);
        }
  return image;
}

LabelImage4 appearing_ball_phantom(const Dims4& dims, const Vec4& spacing,
                                   std::size_t first_frame) {
  const double frames = double(dims[3]);
  const double beat_x = 0.28 * double(dims[0]) * spacing[0];
  const double ball_x = 0.72 * double(dims[0]) * spacing[0];
  const double cy = 0.5 * double(dims[1]) * spacing[1], cz = 0.5 * double(dims[2]) * spacing[2];
  return voxelize(dims, spacing, [&](const Point4& p) -> Label {
    const double frame = p[3] / spacing[3];
    const double beat = (7 + 2 * std::sin(2 * std::numbers::pi * frame / frames)) * spacing[0];
    // Frames since the ball appeared, around the cycle.
    const double age = std::fmod(frame - double(first_frame) + frames, frames);
    const double life = frames / 2;
    const double grown =
        age > 0 && age < life ? 7 * std::sin(std::numbers::pi * age / life) * spacing[0] : 0;
    const double dy = p[1] - cy, dz = p[2] - cz;
    const double d1 = p[0] - beat_x, d2 = p[0] - ball_x;
    if (d1 * d1 + dy * dy + dz * dz < beat * beat) return 1;
    if (d2 * d2 + dy * dy + dz * dz < grown * grown) return 2;
    return 0;
  });
}

std::vector<std::string> phantom_names() {
  return {"hypersphere",     "hypertorus",     "ventricle",     "blobs",      "thin-wall",
          "checkerboard",    "corner-contact", "island",        "thin-plate", "moving-junction",
          "diagonal-island", "thin-bridge",    "appearing-ball"};
}

LabelImage4 make_phantom(const std::string& name) {
  if (name == "hypersphere") return hypersphere_phantom();
  if (name == "hypertorus") return hypertorus_phantom();
  if (name == "ventricle") return beating_ventricle_phantom();
  if (name == "blobs") return merging_blobs_phantom();
  if (name == "thin-wall") return thin_wall_phantom();
  if (name == "checkerboard") return checkerboard_phantom();
  if (name == "corner-contact") return corner_contact_phantom();
  if (name == "island") return island_phantom();
  if (name == "thin-plate") return thin_plate_phantom();
  if (name == "moving-junction") return moving_junction_phantom();
  if (name == "diagonal-island") return diagonal_island_phantom();
  if (name == "thin-bridge") return thin_bridge_phantom();
  if (name == "appearing-ball") return appearing_ball_phantom();
  std::string known;
  for (const std::string& n : phantom_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown phantom '" + name + "' (known: " + known + ")");
}

}  // namespace mesh4d::domain
