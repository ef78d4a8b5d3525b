// Which drawer draws the LOD renderer's geometry nodes: the tile rasterizer, Embree rays, or the
// cheaper of the two for each frame (lod_geometry.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace pbs {

enum class GeometryDrawer : std::uint32_t { Raster = 0, Rays = 1, Auto = 2 };

// "raster", "rays", "auto"; nullopt for any other name.
std::optional<GeometryDrawer> geometryDrawerFromName(std::string_view name);
const char* geometryDrawerName(GeometryDrawer drawer);

}  // namespace pbs
