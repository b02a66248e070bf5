# Precompiled headers: the third-party headers most sources of a target include are compiled once per target
# and loaded by each source, instead of being parsed by every source again. Parsing OpenVDB's headers costs
# every source that includes them seconds of compiler time, more than the rest of many of those sources take
# (docs/PERFORMANCE.md, build and CI time).
#
# A precompiled header is force-included into every source of its target, so each set below holds only what
# most sources of its targets include anyway: OpenVDB only for sim, thermal and their tests. A target built
# with the same options and at least the same definitions uses another's (REUSE_FROM) rather than compiling
# its own. A header that does not match is an error (-Winvalid-pch under -Werror), not a silently slow build.
# -DBEADTWIN_PCH=OFF builds without them: each source then has to include all it uses to compile.
option(BEADTWIN_PCH "Precompile the third-party headers each library and test program includes" ON)

# ccache caches a compile that uses a precompiled header only when it may ignore the header's #defines and
# the time macros (ccache's manual, "Precompiled headers"); without that every such compile is a miss. When
# the compiler launcher is ccache, the build adds that sloppiness to the user's own (which it reads here), so
# ccache keeps working with the precompiled headers (beadtwin uses no time macros). Clang writes the header's
# time into its precompiled header unless told not to, which would make every rebuilt header a new one to
# ccache.
if(BEADTWIN_PCH)
  foreach(_lang C CXX)
    set(_launcher "${CMAKE_${_lang}_COMPILER_LAUNCHER}")
    list(LENGTH _launcher _n)
    if(_n EQUAL 1 AND _launcher MATCHES "ccache$")
      execute_process(COMMAND ${_launcher} --get-config sloppiness OUTPUT_VARIABLE _sloppiness
                      OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      string(REGEX REPLACE "[, ]+" ";" _sloppiness "${_sloppiness}")
      list(APPEND _sloppiness pch_defines time_macros)
      list(REMOVE_DUPLICATES _sloppiness)
      list(REMOVE_ITEM _sloppiness "")
      list(JOIN _sloppiness "," _sloppiness)
      set(CMAKE_${_lang}_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_SLOPPINESS=${_sloppiness}
                                          ${_launcher})
      if(CMAKE_${_lang}_COMPILER_ID STREQUAL "Clang")
        add_compile_options("$<$<COMPILE_LANGUAGE:${_lang}>:SHELL:-Xclang -fno-pch-timestamp>")
      endif()
    endif()
  endforeach()
endif()

# What most sources of the libraries include: the standard containers, Eigen and fmt.
set(BEADTWIN_PCH_BASE <algorithm> <functional> <map> <memory> <optional> <string> <string_view> <vector>
                      <Eigen/Core> <Eigen/Geometry> <fmt/format.h>)
# The libraries that hold voxels (sim, thermal): OpenVDB besides.
set(BEADTWIN_PCH_VOXELS ${BEADTWIN_PCH_BASE} <openvdb/openvdb.h>)

# Precompiles HEADERS for TARGET, or with REUSE_FROM uses those of another target built with the same options.
#   beadtwin_precompile(TARGET HEADERS header...)
#   beadtwin_precompile(TARGET REUSE_FROM OTHER)
function(beadtwin_precompile target)
  cmake_parse_arguments(PARSE_ARGV 1 _pch "" "REUSE_FROM" "HEADERS")
  if(NOT BEADTWIN_PCH)
    return()
  endif()
  if(_pch_REUSE_FROM)
    target_precompile_headers(${target} REUSE_FROM ${_pch_REUSE_FROM})
  else()
    target_precompile_headers(${target} PRIVATE ${_pch_HEADERS})
  endif()
endfunction()
