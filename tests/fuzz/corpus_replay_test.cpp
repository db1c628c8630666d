// Replays every seed and every past finding of the fuzz targets (fuzz/corpus, fuzz/regressions)
// through the same handling as the libFuzzer executables, in the ordinary build: a decoder
// change that brings back a fixed crash, or breaks a seed's property, fails here. A finding
// aborts the process; the file being replayed is printed first, so the log names it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <vector>

#include "fuzz_inputs.h"

namespace fs = std::filesystem;

namespace {

std::size_t replay(const std::string& target, void (*exercise)(const std::uint8_t*, std::size_t)) {
  std::size_t count = 0;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path dir = fs::path(MESH4D_FUZZ_DIR) / kind / target;
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      std::ifstream in(entry.path(), std::ios::binary);
      const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
      std::cerr << "replaying " << entry.path() << "\n";
      exercise(bytes.data(), bytes.size());
      ++count;
    }
  }
  return count;
}

TEST(FuzzCorpusReplay, UploadDecoder) {
  EXPECT_GE(replay("upload_decoder", mesh4d::fuzz::exercise_upload_decoder), 8u);
}

TEST(FuzzCorpusReplay, M4dReader) {
  EXPECT_GE(replay("m4d_reader", mesh4d::fuzz::exercise_m4d_reader), 4u);
}

}  // namespace
