// `pbs view` without --surfels: the scene is shown exactly at once, and the page can ask for surfels to be
// made in the background (the same surfelize as `pbs surfelize`, on the scene as loaded), with progress
// it polls; once written, the file is handed to the renderer and the page can draw with it.
#pragma once

#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>

#include <nlohmann/json.hpp>

#include <atomic>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace pbs::cli {

class BackgroundSurfelize {
 public:
  // `scene` and `hierarchy` must outlive this object and stay unchanged. `path` is where the file goes;
  // `done` is called with it from the background thread once it is written.
  BackgroundSurfelize(const Scene& scene, const Hierarchy& hierarchy, std::filesystem::path path,
                      std::function<void(const std::filesystem::path&)> done);
  // Stops a run in progress (at its next finished array; nothing is left of its file) and waits for it.
  ~BackgroundSurfelize();
  BackgroundSurfelize(const BackgroundSurfelize&) = delete;
  BackgroundSurfelize& operator=(const BackgroundSurfelize&) = delete;

  // Starts making the surfels unless a run has started already; returns whether this call started one.
  bool start();
  // {"state": "idle" | "running" | "done" | "failed", "fraction": 0…1, "arrays_done", "arrays_total",
  //  "seconds", "file", and "error" when it failed}.
  nlohmann::json status() const;

 private:
  void run();

  const Scene& scene_;
  const Hierarchy& hierarchy_;
  const std::filesystem::path path_;
  const std::function<void(const std::filesystem::path&)> done_;
  std::atomic<bool> stopping_{false};
  mutable std::mutex mutex_;  // guards the status below
  std::string state_ = "idle";
  double fraction_ = 0.0;
  std::uint32_t arraysDone_ = 0, arraysTotal_ = 0;
  double seconds_ = 0.0;
  std::string error_;
  std::thread thread_;
};

}  // namespace pbs::cli
