// The orbit, approach and flythrough paths of camera_paths.hpp.
#include "pbs/surfels/camera_paths.hpp"

#include "pbs/raster/value_names.hpp"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pbs {
namespace {

constexpr ValueNames<CameraPath, 3> kPathNames{
    {{{CameraPath::Orbit, "orbit"}, {CameraPath::Approach, "approach"}, {CameraPath::Flythrough, "flythrough"}}}};

// The scene's box relative to its centre, with a box of no diagonal replaced as the header says.
struct SceneFrame {
  glm::dvec3 center{0.0};
  glm::dvec3 lo{0.0}, hi{0.0};  // box corners relative to `center`
  double radius = 1.0;          // half the diagonal, > 0
};

SceneFrame sceneFrame(const Bounds& bounds) {
  SceneFrame frame;
  if (!bounds.empty()) frame.center = bounds.center();
  const double radius = 0.5 * glm::length(bounds.size());
  if (radius > 0.0) {
    frame.lo = bounds.min - frame.center;
    frame.hi = bounds.max - frame.center;
    frame.radius = radius;
  } else {
    frame.hi = glm::dvec3(1.0 / std::sqrt(3.0));
    frame.lo = -frame.hi;
  }
  return frame;
}

// glm::lookAt(eye, eye + forward, +Y) without forming eye + forward, which would round away the
// direction's digits far from the origin.
glm::dmat4 viewAlong(const glm::dvec3& eye, const glm::dvec3& forward) {
  const glm::dvec3 f = forward;
  const glm::dvec3 s = glm::normalize(glm::cross(f, glm::dvec3(0.0, 1.0, 0.0)));
  const glm::dvec3 u = glm::cross(s, f);
  glm::dmat4 view(1.0);
  view[0][0] = s.x;
  view[1][0] = s.y;
  view[2][0] = s.z;
  view[0][1] = u.x;
  view[1][1] = u.y;
  view[2][1] = u.z;
  view[0][2] = -f.x;
  view[1][2] = -f.y;
  view[2][2] = -f.z;
  view[3][0] = -glm::dot(s, eye);
  view[3][1] = -glm::dot(u, eye);
  view[3][2] = glm::dot(f, eye);
  return view;
}

// A camera at `offset` from the scene's centre looking along unit `forward`: near and far bracket
// the bounding sphere from the eye, near no closer than 1e-3 R so 32-bit depth keeps its precision.
PathView viewAt(const SceneFrame& frame, const glm::dvec3& offset, const glm::dvec3& forward, std::uint32_t width,
                std::uint32_t height) {
  PathView view;
  view.eye = frame.center + offset;
  view.forward = forward;
  const double distance = glm::length(offset);
  const double near = std::max(distance - frame.radius, 1e-3 * frame.radius);
  const double far = distance + frame.radius;
  view.camera =
      perspectiveCamera(viewAlong(view.eye, forward), glm::radians(kOrbitFovYDegrees), near, far, width, height);
  const double azimuth = glm::degrees(std::atan2(-forward.z, -forward.x));
  view.azimuthDegrees = forward.x == 0.0 && forward.z == 0.0 ? 0.0 : azimuth < 0.0 ? azimuth + 360.0 : azimuth;
  return view;
}

std::vector<PathView> orbitPath(const Bounds& bounds, const Orbit& orbit, std::uint32_t frames, std::uint32_t width,
                                std::uint32_t height) {
  // The arithmetic of the orbit `pbs render` and `pbs eval` used before paths, so orbits keep their bits.
  const glm::dvec3 center = bounds.empty() ? glm::dvec3(0.0) : bounds.center();
  const double radius = 0.5 * glm::length(bounds.size());
  std::vector<PathView> views;
  views.reserve(frames);
  for (std::uint32_t f = 0; f < frames; ++f) {
    Orbit step = orbit;
    step.azimuthDegrees += 360.0 * f / frames;
    PathView view;
    view.camera = orbitCamera(center, radius, step, width, height);
    const glm::dmat4& v = view.camera.view;
    view.eye = glm::dvec3(glm::inverse(v)[3]);
    view.forward = -glm::dvec3(v[0][2], v[1][2], v[2][2]);  // look-at's unit direction, its third row
    view.azimuthDegrees = step.azimuthDegrees;
    views.push_back(view);
  }
  return views;
}

// Distance from the box's centre along unit `dir` to its surface (0 for a box flat across dir).
double exitDistance(const glm::dvec3& halfExtents, const glm::dvec3& dir) {
  double t = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis)
    if (dir[axis] != 0.0) t = std::min(t, halfExtents[axis] / std::abs(dir[axis]));
  return t;
}

std::vector<PathView> approachPath(const Hierarchy& hierarchy, std::span<const std::uint32_t> roots,
                                   const SceneFrame& frame, const Orbit& orbit, std::uint32_t frames,
                                   std::uint32_t width, std::uint32_t height) {
  const Bounds region = approachRegion(hierarchy, roots);
  glm::dvec3 target(0.0), halfExtents = 0.5 * (frame.hi - frame.lo);
  if (!region.empty() && glm::length(region.size()) > 0.0) {
    target = region.center() - frame.center;
    halfExtents = 0.5 * region.size();
  }
  const double regionRadius = glm::length(halfExtents);
  const glm::dvec3 dir = orbitDirection(orbit);
  const double start = glm::length(target) + std::max(orbit.distance, kApproachMinStart) * frame.radius;
  const double end = std::max(0.5 * exitDistance(halfExtents, dir), 1e-3 * regionRadius);
  std::vector<PathView> views;
  views.reserve(frames);
  for (std::uint32_t f = 0; f < frames; ++f) {
    const double distance = frames == 1 ? start : start * std::pow(end / start, double(f) / (frames - 1));
    views.push_back(viewAt(frame, target + dir * distance, -dir, width, height));
  }
  return views;
}

// Where the triangles lie in XZ, relative to the scene's centre: the mean and standard deviation of
// the centres of the nodes' own meshes' boxes, each weighted by its triangles (instances counted).
struct Spread {
  glm::dvec2 mean{0.0}, deviation{0.0};
};

Spread triangleSpread(const Hierarchy& hierarchy, std::span<const std::uint32_t> roots, const SceneFrame& frame) {
  std::vector<char> inside(hierarchy.parent.size(), 0);
  for (std::uint32_t root : roots) inside[root] = 1;
  std::vector<std::uint64_t> own(hierarchy.subtreeTriangles);
  for (std::uint32_t n : hierarchy.preorder)
    if (const std::int32_t p = hierarchy.parent[n]; p >= 0) {
      inside[n] = inside[std::size_t(p)];
      own[std::size_t(p)] -= hierarchy.subtreeTriangles[n];
    }
  double total = 0.0;
  glm::dvec2 sum(0.0), squares(0.0);
  for (std::uint32_t n : hierarchy.preorder) {
    if (!inside[n] || own[n] == 0 || hierarchy.worldBounds[n].empty()) continue;
    const glm::dvec3 c = hierarchy.worldBounds[n].center() - frame.center;
    const double w = double(own[n]);
    total += w;
    sum += w * glm::dvec2(c.x, c.z);
    squares += w * glm::dvec2(c.x * c.x, c.z * c.z);
  }
  if (!(total > 0.0)) return {};
  Spread spread;
  spread.mean = sum / total;
  spread.deviation = glm::sqrt(glm::max(squares / total - spread.mean * spread.mean, glm::dvec2(0.0)));
  return spread;
}

std::vector<PathView> flythroughPath(const Hierarchy& hierarchy, std::span<const std::uint32_t> roots,
                                     const SceneFrame& frame, std::uint32_t frames, std::uint32_t width,
                                     std::uint32_t height) {
  const glm::dvec3 size = frame.hi - frame.lo;
  const Spread spread = triangleSpread(hierarchy, roots, frame);
  // The loop's centre and semi-axes per horizontal axis: around the triangles, inside the box.
  const auto axis = [&](int a, int s) {
    const double floor = 1e-3 * frame.radius;
    const double centre = std::clamp(spread.mean[s], frame.lo[a] + 2.0 * floor, frame.hi[a] - 2.0 * floor);
    const double room = kFlyRoom * std::min(centre - frame.lo[a], frame.hi[a] - centre);
    return glm::dvec2(centre, std::max(std::min(kFlySpread * spread.deviation[s], room), floor));
  };
  const glm::dvec2 x = axis(0, 0), z = axis(2, 1);
  const double ex = x[1], ez = z[1];
  const double h = std::max(size.y, kFlyFlatHeight * std::max(size.x, size.z));
  const double middle = 0.5 * (kFlyLowHeight + kFlyHighHeight), wave = 0.5 * (kFlyHighHeight - kFlyLowHeight);
  const auto eyeAt = [&](double theta) {
    return glm::dvec3(x[0] + ex * std::cos(theta), frame.lo.y + h * (middle - wave * std::cos(2.0 * theta)),
                      z[0] + ez * std::sin(theta));
  };
  // Arc length along a fine polygon of the loop, so frames are evenly spaced however stretched the
  // ellipse: frame f sits at the angle where the length reaches f/frames of the whole.
  constexpr std::size_t kSegments = 8192;
  std::vector<double> length(kSegments + 1, 0.0);
  glm::dvec3 previous = eyeAt(0.0);
  for (std::size_t i = 1; i <= kSegments; ++i) {
    const glm::dvec3 next = eyeAt(glm::two_pi<double>() * double(i) / kSegments);
    length[i] = length[i - 1] + glm::length(next - previous);
    previous = next;
  }
  const double pitch = glm::radians(kFlyPitchDegrees);
  std::vector<PathView> views;
  views.reserve(frames);
  for (std::uint32_t f = 0; f < frames; ++f) {
    const double wanted = length[kSegments] * f / frames;
    const std::size_t i = std::size_t(std::upper_bound(length.begin(), length.end(), wanted) - length.begin()) - 1;
    const double span = length[i + 1] - length[i];
    const double within = span > 0.0 ? (wanted - length[i]) / span : 0.0;
    const double theta = glm::two_pi<double>() * (double(i) + within) / kSegments;
    const glm::dvec3 tangent = glm::normalize(glm::dvec3(-ex * std::sin(theta), 0.0, ez * std::cos(theta)));
    const glm::dvec3 forward = std::cos(pitch) * tangent + glm::dvec3(0.0, -std::sin(pitch), 0.0);
    views.push_back(viewAt(frame, eyeAt(theta), forward, width, height));
  }
  return views;
}

}  // namespace

Bounds sceneBounds(const Hierarchy& hierarchy, std::span<const std::uint32_t> roots) {
  Bounds bounds;  // as summarizeScene unites them, so the orbit matches `pbs render`'s bit for bit
  for (std::uint32_t root : roots) bounds.extend(hierarchy.worldBounds[root]);
  return bounds;
}

std::optional<CameraPath> cameraPathFromName(std::string_view name) { return kPathNames.parse(name); }

const char* cameraPathName(CameraPath path) { return kPathNames.name(path).data(); }

Bounds approachRegion(const Hierarchy& hierarchy, std::span<const std::uint32_t> roots) {
  const Bounds scene = sceneBounds(hierarchy, roots);
  const double wanted = kApproachRegionFraction * glm::length(scene.size());
  // The child with the most triangles of every node, found in one pass over the parents.
  std::vector<std::int32_t> heaviest(hierarchy.parent.size(), -1);
  const auto heavier = [&](std::uint32_t a, std::int32_t b) {
    return b < 0 || hierarchy.subtreeTriangles[a] > hierarchy.subtreeTriangles[std::size_t(b)] ||
           (hierarchy.subtreeTriangles[a] == hierarchy.subtreeTriangles[std::size_t(b)] && std::int32_t(a) < b);
  };
  for (std::uint32_t n : hierarchy.preorder)
    if (const std::int32_t p = hierarchy.parent[n]; p >= 0 && heavier(n, heaviest[std::size_t(p)]))
      heaviest[std::size_t(p)] = std::int32_t(n);
  std::int32_t best = -1;
  for (std::uint32_t root : roots)
    if (heavier(root, best)) best = std::int32_t(root);

  Bounds region = scene;
  const auto qualifies = [&](std::int32_t n) {
    if (n < 0) return false;
    const Bounds& box = hierarchy.worldBounds[std::size_t(n)];
    return !box.empty() && glm::length(box.size()) > 0.0 && glm::length(box.size()) >= wanted;
  };
  while (qualifies(best)) {
    region = hierarchy.worldBounds[std::size_t(best)];
    best = heaviest[std::size_t(best)];
  }
  return region;
}

std::vector<PathView> cameraPath(CameraPath path, const Hierarchy& hierarchy, std::span<const std::uint32_t> roots,
                                 const Orbit& orbit, std::uint32_t frames, std::uint32_t width, std::uint32_t height) {
  frames = std::max(1u, frames);
  const Bounds bounds = sceneBounds(hierarchy, roots);
  switch (path) {
    case CameraPath::Orbit: return orbitPath(bounds, orbit, frames, width, height);
    case CameraPath::Approach: return approachPath(hierarchy, roots, sceneFrame(bounds), orbit, frames, width, height);
    case CameraPath::Flythrough: return flythroughPath(hierarchy, roots, sceneFrame(bounds), frames, width, height);
  }
  return {};
}

}  // namespace pbs
