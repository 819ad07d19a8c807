#pragma once
/// A solved radiosity mesh as a PLY file: one polygon per element with its own corners, each
/// carrying its position, an 8-bit sRGB colour (the radiance B / pi, for any mesh viewer) and
/// the radiosity in floats (for reuse by another render of the same scene).
#include <string>
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/render/radiosity/radiosity_mesh.h"

namespace penumbra {

/// Writes the per-corner radiosity `corners` (4 per element of `mesh`) to `path` (binary PLY,
/// written atomically); `comment` goes into the header.
void write_radiosity_solution(const std::string& path, const RadiosityMesh& mesh,
                              const std::vector<Rgb>& corners, const std::string& comment);

/// Reads a file written by write_radiosity_solution for a mesh built the same way as `mesh`
/// (same scene and patch size): applies the file's adaptive subdivision (its `comment split`
/// lines) to `mesh`, refusing to go beyond `max_elements`, and returns the per-corner
/// radiosity. Throws InputError naming the file, the byte offset or header line and the problem
/// when the file is not such a solution or belongs to another mesh (element count or corner
/// positions differ).
std::vector<Rgb> read_radiosity_solution(const std::string& path, RadiosityMesh& mesh,
                                         size_t max_elements = 200000);

}  // namespace penumbra
