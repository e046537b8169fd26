#pragma once
// Image files of simulated frames: 16-bit label PNGs (the recorder's ground truth) and 8-bit
// previews for looking at worlds (`rasm sim render`).

#include <cstdint>
#include <string>

#include "rasm/core/Image.h"
#include "rasm/core/RgbdFrame.h"

namespace rasm::sim {

/// Lossless 16-bit single-channel PNG (ids as stored, 0 = none). Throws InputError on failure.
void saveLabelPng(const Image<std::uint16_t>& labels, const std::string& path);
/// Reads a PNG written by saveLabelPng; throws InputError naming the path.
Image<std::uint16_t> loadLabelPng(const std::string& path);

/// Writes <prefix>_colour.png, <prefix>_depth.png (false colour, black = missing) and, when the
/// frame has labels, <prefix>_instance.png / <prefix>_class.png (a distinct colour per id).
void savePreviewImages(const RgbdFrame& frame, const std::string& prefix, double max_depth_m = 5.0);

}  // namespace rasm::sim
