// The paths figure: two top views rendered exactly, the three paths drawn over them, and their eyes
// and directions as JSON.
#include "figure_paths.hpp"

#include <pbs/evaluation/contact_sheet.hpp>
#include "image_files.hpp"
#include "scene_report.hpp"
#include <pbs/evaluation/svg_plot.hpp>

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/surfels/camera_paths.hpp>
#include <pbs/surfels/frame_renderer.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <vector>

namespace pbs::cli {
namespace {

using Color = std::array<std::uint8_t, 3>;

constexpr CameraPath kPaths[] = {CameraPath::Orbit, CameraPath::Approach, CameraPath::Flythrough};
constexpr Color kBoxColor = {120, 120, 120};
constexpr Color kHalo = {255, 255, 255};
constexpr std::uint8_t kBackground[3] = {250, 250, 250};
constexpr float kSceneFade = 0.35f;  // the render blended toward white by this much, so the paths stand out

// A square region of the XZ plane a panel shows: centre and half its side (the shorter image side).
struct TopExtent {
  double x = 0.0, z = 0.0, half = 1.0;
};

// Orthographic, looking down −Y from above `bounds`, +X to the right and +Z down the image.
Camera topCamera(const TopExtent& extent, const Bounds& bounds, std::uint32_t width, std::uint32_t height) {
  const double top = bounds.empty() ? 1.0 : bounds.max.y, bottom = bounds.empty() ? -1.0 : bounds.min.y;
  const double margin = std::max(1e-3 * extent.half, 1e-3 * (top - bottom));
  const glm::dvec3 eye(extent.x, top + margin, extent.z);
  glm::dmat4 view(1.0);  // rows: right = +X, up = −Z, back = +Y (right-handed)
  view[0][0] = 1.0;
  view[1][1] = 0.0;
  view[2][1] = -1.0;
  view[1][2] = 1.0;
  view[2][2] = 0.0;
  view[3][0] = -eye.x;
  view[3][1] = eye.z;
  view[3][2] = -eye.y;
  const double aspect = double(width) / double(height);
  const double halfX = extent.half * std::max(1.0, aspect), halfY = extent.half * std::max(1.0, 1.0 / aspect);
  return orthographicCamera(view, -halfX, halfX, -halfY, halfY, 0.0, top - bottom + 2.0 * margin, width, height);
}

// An RGB8 picture of side-by-side panels that clips each drawing to the panel it belongs to.
struct Canvas {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;

  void disc(int panelX, std::uint32_t panelWidth, double x, double y, double radius, const Color& color) {
    const int x0 = std::max(panelX, int(std::floor(x - radius))),
              x1 = std::min(panelX + int(panelWidth) - 1, int(std::ceil(x + radius)));
    const int y0 = std::max(0, int(std::floor(y - radius))), y1 = std::min(int(height) - 1, int(std::ceil(y + radius)));
    for (int py = y0; py <= y1; ++py)
      for (int px = x0; px <= x1; ++px) {
        const double dx = px + 0.5 - x, dy = py + 0.5 - y;
        if (dx * dx + dy * dy > radius * radius) continue;
        std::uint8_t* pixel = &rgb[(std::size_t(py) * width + std::size_t(px)) * 3];
        std::copy(color.begin(), color.end(), pixel);
      }
  }

  // Discs every half pixel along the segment; segments far outside the panel are skipped whole.
  void line(int panelX, std::uint32_t panelWidth, glm::dvec2 a, glm::dvec2 b, double radius, const Color& color) {
    const double limit = 4.0 * (double(panelWidth) + height);
    if (std::max({std::abs(a.x), std::abs(a.y), std::abs(b.x), std::abs(b.y)}) > limit) return;
    const int steps = std::max(1, int(std::ceil(2.0 * glm::length(b - a))));
    for (int i = 0; i <= steps; ++i) {
      const glm::dvec2 p = a + (b - a) * (double(i) / steps);
      disc(panelX, panelWidth, panelX + p.x, p.y, radius, color);
    }
  }
};

glm::dvec2 toPixel(const Camera& camera, const glm::dvec3& world) {
  const glm::dvec3 window = windowFromClip(camera, camera.clipFromWorld() * glm::dvec4(world, 1.0));
  return {window.x, window.y};
}

// The scene rendered exactly from `camera`, as RGBA8 (alpha 0 where nothing was drawn), faded.
std::vector<std::uint8_t> renderTop(const LoadedScene& loaded, const Camera& camera) {
  FrameRenderer exact(loaded.scene, loaded.hierarchy, {.mode = RenderMode::Exact, .lod = {}}, camera.width,
                      camera.height);
  std::vector<glm::vec4> image = exact.render(camera).image;
  for (glm::vec4& pixel : image)
    if (pixel.a > 0.0f) pixel = glm::vec4(glm::mix(glm::vec3(pixel), glm::vec3(1.0f), kSceneFade), pixel.a);
  return toRgba8(image);
}

void outlineBox(Canvas& canvas, int panelX, const Camera& camera, const Bounds& box, double radius,
                const Color& color) {
  if (box.empty()) return;
  const double y = box.max.y;
  const glm::dvec2 corners[4] = {toPixel(camera, {box.min.x, y, box.min.z}), toPixel(camera, {box.max.x, y, box.min.z}),
                                 toPixel(camera, {box.max.x, y, box.max.z}),
                                 toPixel(camera, {box.min.x, y, box.max.z})};
  for (int i = 0; i < 4; ++i) canvas.line(panelX, camera.width, corners[i], corners[(i + 1) % 4], radius, color);
}

void drawPath(Canvas& canvas, int panelX, const Camera& camera, const std::vector<PathView>& views, bool closed,
              double scale, const Color& color) {
  std::vector<glm::dvec2> points;
  for (const PathView& view : views) points.push_back(toPixel(camera, view.eye));
  const std::size_t segments = closed ? points.size() : points.size() - 1;
  for (int pass = 0; pass < 2; ++pass) {  // a white halo first, then the colour over it
    const Color& ink = pass == 0 ? kHalo : color;
    const double grow = pass == 0 ? scale : 0.0;
    for (std::size_t i = 0; i < segments; ++i)
      canvas.line(panelX, camera.width, points[i], points[(i + 1) % points.size()], 1.2 * scale + grow, ink);
    for (std::size_t i = 0; i < views.size(); ++i) {
      const glm::dvec2 heading(views[i].forward.x, views[i].forward.z);  // image x = +X, image y = +Z
      if (glm::length(heading) > 1e-9)
        canvas.line(panelX, camera.width, points[i], points[i] + glm::normalize(heading) * (11.0 * scale),
                    0.8 * scale + grow, ink);
      canvas.disc(panelX, camera.width, panelX + points[i].x, points[i].y, (i == 0 ? 5.0 : 2.5) * scale + grow, ink);
    }
  }
}

void drawLegend(Canvas& canvas, double scale) {
  const double side = 14.0 * scale, gap = 6.0 * scale;
  for (std::size_t p = 0; p < kPathColors.size(); ++p) {
    const double x = gap + p * (side + gap), y = gap;
    for (int py = int(y - 1); py < std::min(int(y + side + 1), int(canvas.height)); ++py)
      for (int px = int(x - 1); px < std::min(int(x + side + 1), int(canvas.width)); ++px) {
        const bool border = py < int(y) || py >= int(y + side) || px < int(x) || px >= int(x + side);
        std::uint8_t* pixel = &canvas.rgb[(std::size_t(py) * canvas.width + std::size_t(px)) * 3];
        const Color& color = border ? kHalo : kPathColors[p];
        std::copy(color.begin(), color.end(), pixel);
      }
  }
}

// The square of the XZ plane around `box` (and the points), `margin` of its half side added.
TopExtent extentAround(const Bounds& box, double margin) {
  const glm::dvec3 size = box.size();
  TopExtent extent{box.center().x, box.center().z, 0.5 * std::max(size.x, size.z)};
  if (!(extent.half > 0.0)) extent.half = std::max(0.5 * size.y, 1.0);
  extent.half *= 1.0 + margin;
  return extent;
}

nlohmann::json vec3Json(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

nlohmann::json boundsJson(const Bounds& box) {
  if (box.empty()) return nullptr;
  return {{"min", vec3Json(box.min)}, {"max", vec3Json(box.max)}};
}

nlohmann::json extentJson(const TopExtent& extent, const Camera& camera) {
  const double halfX = 1.0 / camera.projection[0][0], halfZ = 1.0 / camera.projection[1][1];
  return {{"x", {extent.x - halfX, extent.x + halfX}}, {"z", {extent.z - halfZ, extent.z + halfZ}}};
}

}  // namespace

void writePathsFigure(const PathsFigureOptions& options, const std::filesystem::path& folder) {
  const LoadedScene loaded = loadAndAnalyze(options.scene, LoadOptions{});
  std::filesystem::create_directories(folder);
  const Bounds& bounds = loaded.summary.bounds;
  const std::uint32_t w = options.width, h = options.height;

  std::vector<std::vector<PathView>> paths;
  Bounds everything = bounds;
  for (CameraPath path : kPaths) {
    paths.push_back(cameraPath(path, loaded.hierarchy, loaded.scene.roots, options.orbit, options.frames, w, h));
    for (const PathView& view : paths.back()) everything.extend(view.eye);
  }
  const Bounds region = approachRegion(loaded.hierarchy, loaded.scene.roots);

  const TopExtent extents[2] = {extentAround(everything, 0.06),
                                extentAround(bounds.empty() ? everything : bounds, 0.1)};
  const Camera cameras[2] = {topCamera(extents[0], bounds, w, h), topCamera(extents[1], bounds, w, h)};
  const std::vector<std::uint8_t> overview = renderTop(loaded, cameras[0]), closeUp = renderTop(loaded, cameras[1]);
  Canvas canvas{2 * w, h, contactSheet(w, h, 2, {overview, closeUp}, kBackground)};

  const double scale = std::max(1.0, std::min(w, h) / 512.0);
  for (int panel = 0; panel < 2; ++panel) {
    const int panelX = panel * int(w);
    outlineBox(canvas, panelX, cameras[panel], bounds, 0.6 * scale, kBoxColor);
    outlineBox(canvas, panelX, cameras[panel], region, 0.8 * scale, kPathColors[1]);
    // The approach last, so its end, deep in the scene, is drawn over the flythrough.
    for (std::size_t p : {std::size_t(0), std::size_t(2), std::size_t(1)})
      drawPath(canvas, panelX, cameras[panel], paths[p], kPaths[p] != CameraPath::Approach, scale, kPathColors[p]);
  }
  for (std::uint32_t y = 0; y < h; ++y)  // a line between the panels
    std::copy(kBoxColor.begin(), kBoxColor.end(), &canvas.rgb[(std::size_t(y) * canvas.width + w) * 3]);
  drawLegend(canvas, scale);
  writeImage8(folder / "paths.png", canvas.width, canvas.height, 3, canvas.rgb);

  nlohmann::json json = {
      {"figure", "paths"},
      {"scene", loaded.name},
      {"orbit", {options.orbit.azimuthDegrees, options.orbit.elevationDegrees, options.orbit.distance}},
      {"frames", paths.front().size()},
      {"bounds", boundsJson(bounds)},
      {"approach_region", boundsJson(region)},
      {"image",
       {{"file", "paths.png"},
        {"panel_width", w},
        {"panel_height", h},
        {"view", "top: orthographic, looking down -Y, +X right, +Z down"},
        {"panels", {extentJson(extents[0], cameras[0]), extentJson(extents[1], cameras[1])}}}},
      {"paths", nlohmann::json::object()}};
  for (std::size_t p = 0; p < paths.size(); ++p) {
    nlohmann::json frames = nlohmann::json::array();
    for (const PathView& view : paths[p])
      frames.push_back(
          {{"eye", vec3Json(view.eye)}, {"forward", vec3Json(view.forward)}, {"azimuth", view.azimuthDegrees}});
    json["paths"][cameraPathName(kPaths[p])] = {
        {"color", kPathColors[p]}, {"closed", kPaths[p] != CameraPath::Approach}, {"views", frames}};
  }
  writeTextFile(folder / "paths.json", json.dump(2) + "\n");
  std::printf("%s: %u frames per path; wrote %s/{paths.png, paths.json}\n", loaded.name.c_str(),
              std::uint32_t(paths.front().size()), folder.string().c_str());
}

}  // namespace pbs::cli
