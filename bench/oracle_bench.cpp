// oracle_bench: the surface oracle's set-up and query costs on the beating-ventricle phantom at
// the paper's size (100×100×44×15) and at twice the resolution (200×200×100×30). References in
// the same run: ITK's Signed Maurer distance map (distances only, the paper's choice) and, on
// the smaller image, ITK's Danielsson map (distances and closest-voxel vectors).
//
// Then the set-up on the job's threads against one thread, in the same run.
//
//   oracle_bench [--skip-large] [--threads 1,2]
#include <itkDanielssonDistanceMapImageFilter.h>
#include <itkImage.h>
#include <itkSignedMaurerDistanceMapImageFilter.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "domain/feature_transform.h"
#include "domain/phantoms.h"
#include "domain/surface_oracle.h"

using namespace mesh4d::domain;
using Clock = std::chrono::steady_clock;

namespace {

// While it runs, the feature transform holds a 4-byte feature and an 8-byte squared distance
// per voxel (feature_transform.cpp); afterwards only the features stay.
constexpr double kPeakBytesPerVoxel = sizeof(std::uint32_t) + sizeof(double);
volatile double g_sink;  // keeps the query results alive

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

using Binary = itk::Image<std::uint8_t, 4>;
using Distance = itk::Image<float, 4>;

Binary::Pointer foreground_of(const LabelImage4& image) {
  auto out = Binary::New();
  Binary::SizeType size;
  Binary::SpacingType spacing;
  for (unsigned a = 0; a < 4; ++a) size[a] = image.dims()[a], spacing[a] = image.spacing()[a];
  out->SetRegions(Binary::RegionType(size));
  out->SetSpacing(spacing);
  out->Allocate();
  for (std::size_t i = 0; i < image.voxel_count(); ++i)
    out->GetBufferPointer()[i] = image.at(i) != 0;
  return out;
}

double maurer_seconds(const LabelImage4& image) {
  const auto input = foreground_of(image);
  const auto t0 = Clock::now();
  auto maurer = itk::SignedMaurerDistanceMapImageFilter<Binary, Distance>::New();
  maurer->SetInput(input);
  maurer->SetUseImageSpacing(true);
  maurer->SetSquaredDistance(false);
  maurer->SetNumberOfWorkUnits(1);
  maurer->Update();
  return seconds_since(t0);
}

double danielsson_seconds(const LabelImage4& image) {
  const auto input = foreground_of(image);
  const auto t0 = Clock::now();
  auto danielsson = itk::DanielssonDistanceMapImageFilter<Binary, Distance>::New();
  danielsson->SetInput(input);
  danielsson->InputIsBinaryOn();
  danielsson->UseImageSpacingOn();
  danielsson->SetNumberOfWorkUnits(1);
  danielsson->Update();
  return seconds_since(t0);
}

void run(const char* name, const LabelImage4& image, bool with_danielsson) {
  const double voxels = double(image.voxel_count());
  const auto t0 = Clock::now();
  const SurfaceOracle oracle(image);
  const double ours = seconds_since(t0);
  const double maurer = maurer_seconds(image);
  const double danielsson = with_danielsson ? danielsson_seconds(image) : 0;

  // cfp from random points of the image's box, and label lookups.
  const auto box = image.bounds();
  std::mt19937_64 rng(7);
  std::vector<mesh4d::Point4> queries(20000);
  for (auto& q : queries)
    for (int a = 0; a < 4; ++a)
      q[a] = std::uniform_real_distribution<double>(box[0][a], box[1][a])(rng);
  auto t1 = Clock::now();
  double sink = 0;
  for (const auto& q : queries) sink += oracle.closest_surface_point(q).point[0];
  const double cfp_rate = queries.size() / seconds_since(t1);
  t1 = Clock::now();
  for (const auto& q : queries)
    sink += oracle.closest_surface_point(q, SurfaceOracle::CfpMode::ray).point[0];
  const double ray_rate = queries.size() / seconds_since(t1);
  t1 = Clock::now();
  for (int r = 0; r < 50; ++r)
    for (const auto& q : queries) sink += oracle.label_at(q);
  const double label_rate = 50 * queries.size() / seconds_since(t1);

  std::printf("| %s | %.1fM | %.2f | %.2f | %.2fx | %s | %.0f | %.0f | %.2f | %.0f | %.1f |\n",
              name, voxels / 1e6, ours, maurer, maurer / ours,
              with_danielsson ? (std::to_string(danielsson).substr(0, 5) + " s").c_str() : "-",
              cfp_rate, ray_rate, label_rate / 1e6, double(oracle.memory_bytes()) / voxels,
              kPeakBytesPerVoxel);
  g_sink = sink;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// The oracle's set-up on the job's threads: the feature transform alone and the whole
// constructor, medians of 3 runs, the thread counts interleaved.
void threads_table(const char* name, const LabelImage4& image,
                   const std::vector<unsigned>& threads) {
  std::vector<std::vector<double>> transform(threads.size()), oracle(threads.size());
  for (int r = 0; r < 3; ++r)
    for (std::size_t i = 0; i < threads.size(); ++i) {
      auto t0 = Clock::now();
      g_sink = double(feature_transform(image, threads[i])[0]);
      transform[i].push_back(seconds_since(t0));
      t0 = Clock::now();
      const SurfaceOracle o(image, {}, threads[i]);
      oracle[i].push_back(seconds_since(t0));
    }
  for (std::size_t i = 0; i < threads.size(); ++i)
    std::printf("| %s | %u | %.3f | %.2fx | %.3f | %.2fx |\n", name, threads[i],
                median(transform[i]), median(transform[0]) / median(transform[i]),
                median(oracle[i]), median(oracle[0]) / median(oracle[i]));
}

}  // namespace

int main(int argc, char** argv) {
  bool skip_large = false;
  for (int i = 1; i < argc; ++i)
    skip_large = skip_large || std::strcmp(argv[i], "--skip-large") == 0;
  std::printf("Surface oracle on the beating-ventricle phantom, one thread\n");
  std::printf(
      "| image | voxels | mesh4d feature transform s | ITK Maurer (distances only) s | "
      "Maurer / ours | ITK Danielsson (vectors) | cfp/s (descent) | cfp/s (ray) | label lookups "
      "M/s | kept B/voxel | peak B/voxel while computing |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n");
  run("100x100x44x15", beating_ventricle_phantom({100, 100, 44, 15}, {1.77, 1.77, 6, 1}), true);
  if (!skip_large)
    run("200x200x100x30", beating_ventricle_phantom({200, 200, 100, 30}, {0.885, 0.885, 2.64, 0.5}),
        false);
  // --threads 1,2,4: the set-up on several threads against one, measured in the same run.
  std::vector<unsigned> threads = {1, 2};
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--threads") == 0) {
      threads.clear();
      std::stringstream list(argv[i + 1]);
      for (std::string item; std::getline(list, item, ',');)
        threads.push_back(static_cast<unsigned>(std::stoul(item)));
    }
  std::printf(
      "\nThe set-up on threads (medians of 3, interleaved)\n| image | threads | feature transform "
      "s | speedup | whole oracle s | speedup |\n|---|---|---|---|---|---|\n");
  threads_table("100x100x44x15", beating_ventricle_phantom({100, 100, 44, 15}, {1.77, 1.77, 6, 1}),
                threads);
  return 0;
}
