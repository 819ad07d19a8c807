#pragma once
/// pbrt-v4 shapes as penumbra shapes: trianglemesh, plymesh, sphere, bilinearmesh and disk.
#include <string>
#include <vector>

#include "penumbra/core/transform.h"
#include "penumbra/scene/pbrt_params.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// What a Shape directive needs from the graphics state.
struct PbrtShapeContext {
  Transform to_world;  ///< object to penumbra's world (pbrt's CTM, mirrored when needed)
  bool reverse_orientation = false;
  /// Directories that relative file names are tried in, in order (the including file's, then
  /// the main scene file's).
  std::vector<std::string> search_dirs;
};

/// The shapes of one Shape directive, geometry and transform only (material and emission are the
/// caller's). Empty, with a warning, for shapes that are skipped; malformed ones are InputErrors.
std::vector<ShapeDesc> map_pbrt_shape(const PbrtEntity& shape, const PbrtShapeContext& context,
                                      std::vector<std::string>& warnings);

/// The content of the file at `path`, decompressed with zlib when its name ends in ".gz"
/// (pbrt-v4 scenes ship gzip-compressed meshes and scene files); errors at `loc`.
std::string pbrt_read_file(const std::string& path, const PbrtLoc& loc);

/// The first of `dirs` / `file` that exists (or `file` itself when absolute or none exists).
std::string pbrt_resolve(const std::string& file, const std::vector<std::string>& dirs);

}  // namespace penumbra
