// Named, timed pipeline stages. One place prints progress and keeps per-stage timing,
// so the runner reads like the pipeline and the report can say where the time went.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <mutex>
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
    const Timer timer{this, &name, &Stages::finish};
    return work();
  }

  // Records a stage run elsewhere (before this object existed) as if run here.
  void record(const std::string& name, double seconds) { finish(name, seconds); }

  // Runs `work` as a go of the stage `name` on any thread, without a word (unless `announce`: then the
  // start is heard as run() does): its time adds up with the stage's other goes until record_aside(name)
  // records them here, so the stages keep one order whichever thread ran them.
  template <class F>
  auto run_aside(const std::string& name, F&& work, bool announce = false) {
    if (announce && on_start_) on_start_(name);
    const Timer timer{this, &name, &Stages::add_aside};
    return work();
  }
  // Records the stage `name` run aside, its goes added up; nothing when it never ran.
  void record_aside(const std::string& name);

  const std::vector<StageTime>& times() const { return times_; }

 private:
  // Hands the seconds from its making to its end (a stage's work done or thrown) to `done`.
  struct Timer {
    Stages* self;
    const std::string* name;
    void (Stages::*done)(const std::string&, double);
    std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
    ~Timer() {
      (self->*done)(*name, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  };
  void finish(const std::string& name, double seconds);
  void add_aside(const std::string& name, double seconds);

  std::function<void(const std::string&)> log_;
  std::function<void(const std::string&)> on_start_;
  std::vector<StageTime> times_;
  std::mutex aside_mutex_;
  std::map<std::string, double> aside_;  // seconds of the stages run aside, not yet recorded
};

}  // namespace beadtwin
