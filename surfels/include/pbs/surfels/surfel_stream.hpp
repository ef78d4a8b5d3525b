// A scene's .surfels file and meshes as if they came over a link of fixed bandwidth (the paper's
// conclusion: "While the surfel arrays are transmitted, the already received prefix can be used as an
// approximation … further transmissions then refine the approximation progressively"). Frames draw
// what has arrived; the link spends its bytes where the current view lacks most.
//
// The model, deterministic and independent of how fast frames are drawn: the link delivers bytes at a
// fixed rate on a simulated clock that the caller advances. First come the file's header and tables
// (without them no array's size or place is known); then, each time the clock advances, the chunks and
// meshes the view from the camera lacks, the transfer that fills the most missing pixels per byte first
// (a missing surfel lacks its point's area, a missing mesh the area of its nodes' boxes). A transfer
// starts only once the bytes for the whole of it have accrued; what is left over waits for the next
// advance, unless the view lacks nothing, when an idle link banks nothing. The scene's hierarchy,
// transforms and materials are taken as known locally; textures are not counted.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/lod_render.hpp"
#include "pbs/surfels/surfel_cache.hpp"

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace pbs {

enum class StreamOrder : std::uint32_t {
  // A chunk at a time; a node draws the part of its prefix that has arrived, with discs grown to close
  // its surface.
  Prefixes = 0,
  // Whole arrays one at a time, each drawn only once complete: what a format whose
  // arrays cannot be cut short would do (the figure's baseline).
  WholeArrays = 1,
};

// "prefixes", "arrays"; nullopt for any other name.
std::optional<StreamOrder> streamOrderFromName(std::string_view name);
const char* streamOrderName(StreamOrder order);

struct StreamOptions {
  double bytesPerSecond = 10e6;
  StreamOrder order = StreamOrder::Prefixes;
};

struct StreamStats {
  double seconds = 0.0;           // on the simulated clock
  std::uint64_t bytes = 0;        // arrived: tables, surfel chunks and meshes
  std::uint64_t surfelBytes = 0;  // of those, surfel chunks with their checksums
  std::uint64_t meshBytes = 0;    // of those, meshes (their arrays: pbs::meshBytes)
  bool tablesArrived = false;
  // What the last advance's view still lacked after its transfers: bytes, and the pixels it would
  // cover (Σ missing surfels × their point area, and the box area of geometry nodes without a mesh).
  // Before the tables have arrived, the tables' bytes (the view's needs are not known yet).
  std::uint64_t missingBytes = 0;
  double missingPixels = 0.0;
};

class SurfelStream {
 public:
  // Everything given must outlive the stream; `cache` must be of this scene, and nothing else may load
  // into it (its prefixes are what has arrived). `lod` is what the frames will draw with.
  SurfelStream(SurfelCache& cache, const Scene& scene, const Hierarchy& hierarchy, const LodOptions& lod,
               const StreamOptions& options);

  // Moves the clock on by `seconds` (≥ 0) and spends the link's bytes on what the view from `camera`
  // lacks, the most missing pixels per byte first.
  void advance(const Camera& camera, double seconds);

  // `draws` (of traverseLod from `camera` with this stream's cache and options) as far as they have
  // arrived: geometry only of meshes that have, each prefix cut at its loaded length with the disc
  // radius that closes the surface with the surfels it keeps; nothing before the tables. Where a mesh
  // has not arrived, the nearest node above it (or itself) with surfels stands in, its whole array
  // drawn as far as that has arrived (the link fetches it along with the mesh, far sooner).
  LodDraws arrived(const LodDraws& draws, const Camera& camera) const;

  const StreamStats& stats() const { return stats_; }

 private:
  struct Need;  // one array or mesh the view lacks (surfel_stream.cpp)
  std::vector<Need> needsOf(const LodDraws& draws, const Camera& camera) const;
  // The stand-ins for the geometry of `draws` whose mesh has not arrived, by node, once each.
  std::vector<LodDraws::Surfels> standIns(const LodDraws& draws, const Camera& camera) const;
  // The pixels the need's draws lack, counting an array's surfels only up to `upTo`.
  double missingPixels(const Need& need, std::size_t upTo) const;
  std::size_t nextLength(const Need& need) const;  // an array's loaded length after its next transfer
  std::uint64_t nextTransferBytes(const Need& need) const;
  double gainPerByte(const Need& need) const;            // missing pixels the next transfer fills, per byte
  void transfer(const Need& need, std::uint64_t bytes);  // `bytes`: nextTransferBytes(need)

  SurfelCache& cache_;
  const Scene& scene_;
  const Hierarchy& hierarchy_;
  LodOptions lod_;
  StreamOptions options_;
  std::vector<char> meshArrived_;
  double credit_ = 0.0;  // bytes accrued and not yet spent
  StreamStats stats_;
};

}  // namespace pbs
