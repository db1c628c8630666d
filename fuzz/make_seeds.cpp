// Writes the seed corpora of the fuzz targets (fuzz/corpus/<target>/): a few small, valid inputs
// of every kind each decoder reads, from which libFuzzer's mutations start. The corpora are kept
// in the repository; this tool is how they were made and how to remake them:
//   mesh4d-fuzz-seeds fuzz/corpus
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "domain/image_io.h"
#include "mesh/mesh_io.h"
#include "wire/upload_codec.h"

namespace fs = std::filesystem;
using mesh4d::domain::LabelImage4;

namespace {

void write(const fs::path& path, char mode, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.put(mode);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Two labels in a 6×5×4×3 box: a block of 1 with a 2 beside it, moving by one voxel per frame.
LabelImage4 small_image(bool wide) {
  LabelImage4 image({6, 5, 4, 3}, {1.5, 1.5, 2.0, 5.0}, {-3, 0, 1, 0});
  for (std::size_t t = 0; t < 3; ++t)
    for (std::size_t z = 1; z < 3; ++z)
      for (std::size_t y = 1; y < 4; ++y) {
        image.set(1 + t % 2, y, z, t, 1);
        image.set(3 + t % 2, y, z, t, wide ? 300 : 2);
      }
  return image;
}

// The labels as raw little-endian bytes, x fastest, and the NRRD/MetaImage type name.
std::string raw_labels(const LabelImage4& image, bool wide) {
  std::string raw;
  for (std::size_t i = 0; i < image.voxel_count(); ++i) {
    raw += static_cast<char>(image.at(i) & 0xff);
    if (wide) raw += static_cast<char>(image.at(i) >> 8);
  }
  return raw;
}

std::string nrrd(const LabelImage4& image, bool wide) {
  const auto& d = image.dims();
  std::string s = "NRRD0004\ntype: " + std::string(wide ? "uint16" : "uint8") +
                  "\ndimension: 4\nsizes: " + std::to_string(d[0]) + " " + std::to_string(d[1]) +
                  " " + std::to_string(d[2]) + " " + std::to_string(d[3]) +
                  "\nspacings: 1.5 1.5 2 5\nendian: little\nencoding: raw\n\n";
  return s + raw_labels(image, wide);
}

std::string meta_image(const LabelImage4& image) {
  const auto& d = image.dims();
  std::string s = "ObjectType = Image\nNDims = 4\nDimSize = " + std::to_string(d[0]) + " " +
                  std::to_string(d[1]) + " " + std::to_string(d[2]) + " " + std::to_string(d[3]) +
                  "\nElementSpacing = 1.5 1.5 2 5\nElementType = MET_UCHAR\n"
                  "ElementDataFile = LOCAL\n";
  return s + raw_labels(image, false);
}

std::string grpc_upload(const LabelImage4& image) {
  mesh4d::v1::ImageHeader header;
  const std::string data = mesh4d::wire::encode_upload(image, &header);
  const std::string h = header.SerializeAsString();
  return std::string{static_cast<char>(h.size() & 0xff), static_cast<char>(h.size() >> 8)} + h +
         data;
}

// Two pentatopes of labels 1 and 2 sharing a facet, with their boundary tetrahedra.
mesh4d::mesh::Mesh4 small_mesh() {
  mesh4d::mesh::Mesh4 m;
  m.vertices = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}, {1, 1, 1, 1}};
  m.vertex_kinds = {mesh4d::mesh::VertexKind::box,     mesh4d::mesh::VertexKind::feature,
                    mesh4d::mesh::VertexKind::feature, mesh4d::mesh::VertexKind::free,
                    mesh4d::mesh::VertexKind::free,    mesh4d::mesh::VertexKind::free};
  m.pentatopes = {{0, 1, 2, 3, 4}, {5, 1, 2, 3, 4}};
  m.labels = {1, 2};
  m.boundary = {{{1, 2, 3, 4}, 0, 1, 2}, {{0, 2, 3, 4}, 0, 1, 0}, {{5, 2, 3, 4}, 1, 2, 0}};
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: mesh4d-fuzz-seeds CORPUS_DIR (writes CORPUS_DIR/upload_decoder and "
                 "CORPUS_DIR/m4d_reader)\n";
    return 2;
  }
  const fs::path upload = fs::path(argv[1]) / "upload_decoder",
                 m4d = fs::path(argv[1]) / "m4d_reader";
  fs::create_directories(upload);
  fs::create_directories(m4d);

  const LabelImage4 narrow = small_image(false), wide = small_image(true);
  const fs::path scratch = fs::temp_directory_path() / "mesh4d-fuzz-seeds";
  for (const char* suffix : {".nii", ".nii.gz"}) {
    mesh4d::domain::write_nifti(narrow, scratch.string() + suffix);
    write(upload / (std::string("rest") + suffix), 0, read(scratch.string() + suffix));
    fs::remove(scratch.string() + suffix);
  }
  write(upload / "rest.nrrd", 0, nrrd(narrow, false));
  write(upload / "rest-uint16.nrrd", 0, nrrd(wide, true));
  write(upload / "rest.mha", 0, meta_image(narrow));
  // Mode 3: the harness fills in the SHA-256; mode 1 keeps the encoder's (still right here).
  write(upload / "grpc-uint8", 3, grpc_upload(narrow));
  write(upload / "grpc-uint16", 3, grpc_upload(wide));
  write(upload / "grpc-checksummed", 1, grpc_upload(narrow));

  for (const auto& [name, mesh] :
       {std::pair{"two-pentatopes", small_mesh()}, std::pair{"empty", mesh4d::mesh::Mesh4{}}}) {
    const auto bytes = mesh4d::mesh::encode_m4d(mesh);
    const std::string file(bytes.begin(), bytes.end());
    write(m4d / (std::string(name) + ".m4d"), 0, file);
    write(m4d / (std::string(name) + "-sealed"), 1, file.substr(0, file.size() - 32));
  }
  std::cout << "seeds written under " << argv[1] << "\n";
}
