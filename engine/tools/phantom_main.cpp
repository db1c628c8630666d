// mesh4d-phantom: writes a built-in phantom (hypersphere, hypertorus, ventricle, blobs) as a 4D
// NIfTI label image, the demo's and the tests' input.
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>

#include "domain/image_io.h"
#include "domain/phantoms.h"

int main(int argc, char** argv) {
  std::string name;
  std::string out;
  std::string raw;
  CLI::App app{"mesh4d-phantom: write a built-in 4D phantom as NIfTI"};
  app.add_option("phantom", name, "a built-in phantom (domain/phantoms.h)")
      ->required()
      ->check(CLI::IsMember(mesh4d::domain::phantom_names()));
  app.add_option("-o,--out", out, "output file (.nii or .nii.gz)")->required();
  app.add_option("--raw", raw,
                 "also write the labels raw (x fastest, little-endian uint8, or uint16 when a "
                 "label exceeds 255): the service's upload format");
  CLI11_PARSE(app, argc, argv);
  try {
    const auto image = mesh4d::domain::make_phantom(name);
    mesh4d::domain::write_nifti(image, out);
    const auto& d = image.dims();
    if (!raw.empty()) {
      std::ofstream file(raw, std::ios::binary);
      const bool wide = image.storage_bytes() != image.voxel_count();
      for (std::size_t i = 0; i < image.voxel_count(); ++i) {
        const auto l = image.at(i);
        file.put(static_cast<char>(l & 0xff));
        if (wide) file.put(static_cast<char>(l >> 8));
      }
      if (!file) throw std::runtime_error("cannot write " + raw);
    }
    std::cout << name << ": " << d[0] << "x" << d[1] << "x" << d[2] << "x" << d[3] << " voxels -> "
              << out << "\n";
  } catch (const std::exception& e) {
    std::cerr << "mesh4d-phantom: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
