// BackgroundSurfelize: surfelizeToFile on a thread of its own, its progress kept for the page to poll, and
// a stop that ends it by throwing from its progress callback (surfelizeToFile then leaves no file).
#include "background_surfelize.hpp"

#include <pbs/surfels/surfelize.hpp>

#include <chrono>
#include <stdexcept>

namespace pbs::cli {
namespace {

struct Stopped : std::runtime_error {
  Stopped() : std::runtime_error("stopped") {}
};

}  // namespace

BackgroundSurfelize::BackgroundSurfelize(const Scene& scene, const Hierarchy& hierarchy, std::filesystem::path path,
                                         std::function<void(const std::filesystem::path&)> done)
    : scene_(scene), hierarchy_(hierarchy), path_(std::move(path)), done_(std::move(done)) {}

BackgroundSurfelize::~BackgroundSurfelize() {
  stopping_ = true;
  if (thread_.joinable()) thread_.join();
}

bool BackgroundSurfelize::start() {
  const std::lock_guard lock(mutex_);
  if (state_ != "idle" && state_ != "failed") return false;
  if (thread_.joinable()) thread_.join();  // a failed run's thread has ended
  state_ = "running";
  error_.clear();
  thread_ = std::thread([this] { run(); });
  return true;
}

nlohmann::json BackgroundSurfelize::status() const {
  const std::lock_guard lock(mutex_);
  nlohmann::json status = {
      {"state", state_},     {"fraction", fraction_}, {"arrays_done", arraysDone_}, {"arrays_total", arraysTotal_},
      {"seconds", seconds_}, {"file", path_.string()}};
  if (!error_.empty()) status["error"] = error_;
  return status;
}

void BackgroundSurfelize::run() {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  SurfelizeOptions options;
  options.onProgress = [&](const SurfelizeProgress& progress) {
    if (stopping_) throw Stopped();
    const std::lock_guard lock(mutex_);
    // The captures cost about their subtree's triangles (as `pbs surfelize`'s meter counts).
    fraction_ = double(progress.trianglesDone) / double(std::max<std::uint64_t>(progress.trianglesTotal, 1));
    arraysDone_ = progress.arraysDone;
    arraysTotal_ = progress.arraysTotal;
    seconds_ = elapsed();
  };
  try {
    surfelizeToFile(scene_, hierarchy_, options, path_);
    if (!stopping_) done_(path_);
    const std::lock_guard lock(mutex_);
    state_ = "done";
    fraction_ = 1.0;
    seconds_ = elapsed();
  } catch (const std::exception& error) {
    const std::lock_guard lock(mutex_);
    state_ = "failed";
    error_ = error.what();
  }
}

}  // namespace pbs::cli
