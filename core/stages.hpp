// Named, timed pipeline stages. One place prints progress and keeps per-stage timing,
// so the runner reads like the pipeline and the report can say where the time went.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace beadtwin {

// A finished stage and its wall time, s.
struct StageTime {
  std::string name;
  double seconds = 0.0;
};

// Runs the stages of one run by name, times each and keeps the times in the order the stages finished.
class Stages {
 public:
  // `log` receives one line per finished stage; pass an empty function to stay quiet. `on_start`, when
  // given, hears each stage's name as it starts.
  explicit Stages(std::function<void(const std::string&)> log = {},
                  std::function<void(const std::string&)> on_start = {})
      : log_(std::move(log)), on_start_(std::move(on_start)) {}

  // Runs `work` as the stage `name`, timing it.
  template <class F>
  auto run(const std::string& name, F&& work) {
    if (on_start_) on_start_(name);
    const auto t0 = std::chrono::steady_clock::now();
    struct Finish {
      Stages* self;
      const std::string* name;
      std::chrono::steady_clock::time_point t0;
      ~Finish() {
        self->finish(*name, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
    } finish{this, &name, t0};
    return work();
  }

  // Records a stage run elsewhere (before this object existed) as if run here.
  void record(const std::string& name, double seconds) { finish(name, seconds); }

  const std::vector<StageTime>& times() const { return times_; }

 private:
  void finish(const std::string& name, double seconds);

  std::function<void(const std::string&)> log_;
  std::function<void(const std::string&)> on_start_;
  std::vector<StageTime> times_;
};

}  // namespace beadtwin
