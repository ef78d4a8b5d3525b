// calibrateFrameCosts: every cut times every view, the fit is of those frames, and the calibration file
// reads back the costs it wrote or names what is wrong with it.
#include "surfeled_scene.hpp"

#include <pbs/evaluation/frame_calibration.hpp>
#include <pbs/scene/input_error.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace pbs {
namespace {

TEST(FrameCalibration, TimesEveryViewUnderEveryCutAndReadsBackWhatItWrote) {
  const test::SurfeledScene s = test::surfeled(test::twoIdenticalGroups());
  const std::vector<Camera> cameras = test::approachCameras(s, 3);
  const std::vector<CalibrationCut> cuts = calibrationCuts(LodOptions{});
  ASSERT_EQ(cuts.size(), 12u);
  const FrameCalibration calibration =
      calibrateFrameCosts(s.scene, s.hierarchy, {.surfels = &s.surfels}, cameras, cuts, 1, 0.5);
  ASSERT_EQ(calibration.frames.size(), cuts.size() * cameras.size());
  EXPECT_EQ(calibration.fit.frames, calibration.frames.size());
  std::size_t rays = 0;
  for (const CalibrationFrame& frame : calibration.frames) {
    EXPECT_GT(frame.timed.seconds, 0.0);
    EXPECT_LT(frame.timed.geometrySeconds, frame.timed.seconds);
    EXPECT_EQ(frame.timed.work.imagePixels, 160.0 * 120.0);
    rays += frame.timed.drawer == GeometryDrawer::Rays;
  }
  EXPECT_GT(rays, 0u) << "half the cuts draw their geometry by rays";
  // The budget cuts refine past any threshold, so the fit sees frames of mostly triangles too: the largest
  // draws more triangles than the threshold's cut on some view (a budget alone would stop where it stops).
  std::vector<double> thresholdTriangles(cameras.size()), budgetTriangles(cameras.size());
  for (const CalibrationFrame& frame : calibration.frames) {
    if (frame.cut == "threshold=128+geometry=raster") thresholdTriangles[frame.view] = frame.timed.work.triangles;
    if (frame.cut == "primitives=16000000+geometry=raster") budgetTriangles[frame.view] = frame.timed.work.triangles;
  }
  std::size_t finer = 0;
  for (std::size_t v = 0; v < cameras.size(); ++v) finer += budgetTriangles[v] > thresholdTriangles[v];
  EXPECT_GT(finer, 0u);
  const nlohmann::json json = calibrationJson(calibration);
  EXPECT_EQ(json["frames"].size(), calibration.frames.size());
  EXPECT_EQ(frameCostsFromJson(json, "c.json"), calibration.fit.costs);
}

std::string refusal(const nlohmann::json& json) {
  try {
    frameCostsFromJson(json, "c.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FrameCalibration, AFileThatIsNotACalibrationIsRefusedByName) {
  nlohmann::json good = calibrationJson(FrameCalibration{});
  EXPECT_EQ(frameCostsFromJson(good, "c.json"), FrameCosts{});
  EXPECT_NE(refusal(nlohmann::json::array()).find("c.json: not a calibration file"), std::string::npos);
  nlohmann::json json = good;
  json["pbs_frame_costs"] = 3;
  EXPECT_NE(refusal(json).find("c.json: pbs_frame_costs: version 3"), std::string::npos) << refusal(json);
  // Version 1 had no upscale term and no term for triangles on pixels: read with their defaults.
  json = good;
  json["pbs_frame_costs"] = 1;
  json["seconds_per"].erase("upscale_pixel");
  json["seconds_per"].erase("raster_triangle_on_pixels");
  json["seconds_per"].erase("node_weighed");
  EXPECT_EQ(frameCostsFromJson(json, "c.json"), FrameCosts{});
  json["pbs_frame_costs"] = 2;
  EXPECT_EQ(refusal(json), "c.json: seconds_per.raster_triangle_on_pixels: missing");
  json = good;
  json["seconds_per"].erase("surfel");
  EXPECT_EQ(refusal(json), "c.json: seconds_per.surfel: missing");
  json = good;
  json["seconds_per"]["raster_triangle"] = -1e-9;
  EXPECT_NE(refusal(json).find("c.json: seconds_per.raster_triangle: expected seconds"), std::string::npos);
  json["seconds_per"]["raster_triangle"] = "fast";
  EXPECT_NE(refusal(json).find("seconds_per.raster_triangle"), std::string::npos);
}

}  // namespace
}  // namespace pbs
