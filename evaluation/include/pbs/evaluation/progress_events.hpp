// How a long library call reports its steps (making arrays of another ordering, simplifying a scene):
// a program shows them as it likes (the command line as progress bars on stderr), or not at all.
#pragma once

#include <functional>
#include <string>

namespace pbs {

struct ProgressEvents {
  std::function<void(const std::string& step)> begin;
  // `fraction` of the step is done (0…1); `detail` says what (counts, say).
  std::function<void(const std::string& step, double fraction, const std::string& detail)> update;
  std::function<void(const std::string& step, const std::string& detail)> end;

  void begun(const std::string& step) const {
    if (begin) begin(step);
  }
  void updated(const std::string& step, double fraction, const std::string& detail) const {
    if (update) update(step, fraction, detail);
  }
  void ended(const std::string& step, const std::string& detail) const {
    if (end) end(step, detail);
  }
};

}  // namespace pbs
