// Renders the embedded default scene through the installed library and prints what it drew: the
// version, the scene's size, how many pixels of a small exact frame are covered, and how many settings
// a small sweep names.
#include <pbs/pbs.hpp>

#include <cstdio>
#include <vector>

int main() {
  const pbs::ImportResult loaded = pbs::loadScene("default");
  const pbs::Hierarchy hierarchy = pbs::analyzeHierarchy(loaded.scene);
  pbs::Bounds bounds;
  for (const std::uint32_t root : loaded.scene.roots) bounds.extend(hierarchy.worldBounds[root]);
  constexpr std::uint32_t kWidth = 64, kHeight = 48;
  const pbs::Camera camera =
      pbs::orbitCamera(bounds.center(), 0.5 * glm::length(bounds.size()), pbs::Orbit{}, kWidth, kHeight);
  pbs::FrameRenderer renderer(loaded.scene, hierarchy, {.mode = pbs::RenderMode::Exact}, kWidth, kHeight);
  const pbs::FrameResult frame = renderer.render(camera);
  std::size_t covered = 0;
  for (const glm::vec4& pixel : frame.image) covered += pixel.a > 0.0f;
  // The evaluation library too: the settings a sweep of two overdraws beside one peer names.
  const std::vector<pbs::EvalSetting> settings = pbs::evalSettings({"embree=1"}, {"overdraw=2,8"}, pbs::LodOptions{});
  std::printf("pbs %s: %zu nodes, %zu of %u pixels covered, %zu settings\n", PBS_VERSION_STRING,
              loaded.scene.nodes.size(), covered, kWidth * kHeight, settings.size());
  return covered > 0 ? 0 : 1;
}
