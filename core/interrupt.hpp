// Stopping on Ctrl-C (SIGINT) or SIGTERM without losing anything: reports are written atomically at the end
// of a run, so the previous run's stay intact; the handler says what was stopped and exits with 130 (or
// 143). Files half-written when the signal came are left under their temporary names (.tmp-PID-...) and
// removed by the next run (remove_stale_temporaries).
#pragma once

#include <filesystem>
#include <string_view>

namespace beadtwin {

// Installs the handler for SIGINT and SIGTERM.
void install_interrupt_handler();

// What the program is doing, for the handler's message ("baseline: thermal"). Cut to 200 bytes.
void set_interrupt_context(std::string_view what);

// Removes the temporary files and staging folders (.tmp-PID-...) that processes no longer running left in
// `dir` and the folders directly in it. Returns how many.
int remove_stale_temporaries(const std::filesystem::path& dir);

}  // namespace beadtwin
