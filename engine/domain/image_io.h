// Reading and writing label images with ITK: 4D NIfTI (.nii, .nii.gz), MetaImage (.mha, .mhd),
// NRRD (.nrrd, .nhdr), and a series of 3D files stacked along t. Errors are ImageError with the
// file name and what is wrong.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::domain {

/// Registers ITK's NIfTI, MetaImage and NRRD readers and writers (idempotent; the functions
/// below call it). Code that uses ITK's file I/O directly calls it first.
void register_image_formats();

/// An image whose header announces more voxels than the reader was allowed: refused from the
/// header alone, before any voxel is read or inflated.
class ImageTooLarge : public ImageError {
 public:
  using ImageError::ImageError;
};

/// Reads a 4D label image. Integer labels in 0..65535 of any integer pixel type are accepted
/// (uint8, uint16 and int16 are the usual ones); floating-point, multi-component or non-4D files
/// are refused. Remarks (ignored direction cosines, say) are appended to `warnings` if given.
/// max_voxels > 0: a header that announces more throws ImageTooLarge.
LabelImage4 read_label_image(const std::string& path, std::vector<std::string>* warnings = nullptr,
                             std::uint64_t max_voxels = 0);

/// Reads one 3D label file per frame and stacks them along t, frame i at t = i·time_scale.
/// Every frame must have the same size and spacing.
LabelImage4 read_label_frames(const std::vector<std::string>& paths, double time_scale,
                              std::vector<std::string>* warnings = nullptr);

/// Writes a 4D NIfTI file (.nii or .nii.gz), uint8 labels when they fit, uint16 otherwise.
/// NIfTI keeps the x, y, z origin but no time origin: read back, the image starts at t = 0.
void write_nifti(const LabelImage4& image, const std::string& path);

}  // namespace mesh4d::domain
