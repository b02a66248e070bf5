#include "core/stages.hpp"

#include <fmt/format.h>

namespace beadtwin {

void Stages::finish(const std::string& name, double seconds) {
  times_.push_back({name, seconds});
  if (log_) log_(fmt::format("  {:<10} {:8.2f} s", name, seconds));
}

void Stages::add_aside(const std::string& name, double seconds) {
  const std::lock_guard lock(aside_mutex_);
  aside_[name] += seconds;
}

void Stages::record_aside(const std::string& name) {
  double seconds = 0.0;
  {
    const std::lock_guard lock(aside_mutex_);
    const auto it = aside_.find(name);
    if (it == aside_.end()) return;
    seconds = it->second;
    aside_.erase(it);
  }
  finish(name, seconds);
}

}  // namespace beadtwin
