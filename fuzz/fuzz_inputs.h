// What the fuzz targets do with one input, shared by the libFuzzer executables (fuzz/*_fuzzer.cpp)
// and by the replay test that runs the seed corpora and every past crash in the ordinary build
// (tests/fuzz/corpus_replay_test.cpp). Each function returns normally when the decoder accepted
// the input or refused it with its documented error; anything else (another exception, a broken
// property, a sanitizer report) is a finding, reported by calling std::abort.
#pragma once

#include <cstddef>
#include <cstdint>

namespace mesh4d::fuzz {

/// The upload decoders, both faces. The first byte picks one:
/// - even: the rest is a REST body as POST /v1/jobs receives it (NIfTI, gzip, NRRD, MetaImage);
/// - odd: a SubmitJob upload: a 2-byte little-endian length, that many bytes of serialized
///   ImageHeader, then the label data. With bit 1 set, the harness writes the data's true SHA-256
///   into the header, so that mutations get past the checksum to the label checks.
void exercise_upload_decoder(const std::uint8_t* data, std::size_t size);

/// The .m4d reader. The first byte picks: even, the rest is a file as stored; odd, the rest
/// followed by its true SHA-256 (the file's last 32 bytes), so that mutations get past the
/// checksum. A mesh that decodes must encode back to exactly the bytes read.
void exercise_m4d_reader(const std::uint8_t* data, std::size_t size);

}  // namespace mesh4d::fuzz
