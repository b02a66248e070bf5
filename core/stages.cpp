#include "core/stages.hpp"

#include <fmt/format.h>

namespace beadtwin {

void Stages::finish(const std::string& name, double seconds) {
  times_.push_back({name, seconds});
  if (log_) log_(fmt::format("  {:<10} {:8.2f} s", name, seconds));
}

}  // namespace beadtwin
