// The image of a render split by technique family (Renderer::techniqueImages:
// unidirectional, vertex connection, vertex merging), as files.
#pragma once

#include "Image.h"

#include <array>
#include <string>

namespace wv {

// STEM.techniques.exr with one layer per family, and STEM.techniques.png
// showing each pixel's shares of them (luminance; red unidirectional, green
// vertex connection, blue vertex merging), the "relative contributions"
// picture of the VCM talk.
void writeTechniqueImages(const std::string& stem, const std::array<Image, 3>& families);

} // namespace wv
