# Every third-party library comes from Debian's packages (README: quick start). The traps of those
# packages are handled here, once.

find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(fmt REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 QUIET CONFIG)
if(NOT CLI11_FOUND)
  find_path(CLI11_INCLUDE_DIR CLI/CLI.hpp REQUIRED)
  add_library(CLI11::CLI11 INTERFACE IMPORTED)
  target_include_directories(CLI11::CLI11 INTERFACE ${CLI11_INCLUDE_DIR})
endif()

# TBB must be found before OpenVDB, whose find-module looks for it too.
find_package(TBB REQUIRED)

# Debian ships OpenVDB with a find-module only, in its own folder.
list(APPEND CMAKE_MODULE_PATH "/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB")
find_package(OpenVDB REQUIRED)

find_package(embree 3 REQUIRED)

# OpenImageIO: Debian's exported config names /usr/include/opencv4 and the command-line tools (iconvert...),
# which need not be installed, so the library is found by hand instead.
find_path(OIIO_INCLUDE_DIR OpenImageIO/imageio.h REQUIRED)
find_library(OIIO_LIBRARY OpenImageIO REQUIRED)
find_library(OIIO_UTIL_LIBRARY OpenImageIO_Util REQUIRED)
add_library(OpenImageIO::OpenImageIO INTERFACE IMPORTED)
target_include_directories(OpenImageIO::OpenImageIO INTERFACE ${OIIO_INCLUDE_DIR})
target_link_libraries(OpenImageIO::OpenImageIO INTERFACE ${OIIO_LIBRARY} ${OIIO_UTIL_LIBRARY})

# FreeType draws the images' text (render/text.hpp says why not through OpenImageIO).
find_package(Freetype REQUIRED)

# libpng writes the pictures (render/image.cpp says why not through OpenImageIO).
find_package(PNG REQUIRED)

# SUNDIALS 6: CVODE with the serial vector and the dense/band/Krylov solvers.
find_package(SUNDIALS 6 REQUIRED CONFIG)

# Boost, header-only: Boost.Polygon's segment Voronoi diagram for the medial axis (slicer/medial_axis.cpp).
find_package(Boost 1.74 REQUIRED)

# Clipper (polyclipping) through pkg-config.
find_package(PkgConfig REQUIRED)
pkg_check_modules(POLYCLIPPING REQUIRED IMPORTED_TARGET polyclipping)

# assimp reads the part meshes (STL, OBJ, 3MF, AMF, PLY...). Debian's exported target also passes draco,
# minizip, zlib and a static librt stub on to every consumer; libassimp.so records what it needs itself,
# so those are dropped rather than linked into each program.
find_package(assimp 5 CONFIG REQUIRED)
set_target_properties(assimp::assimp PROPERTIES INTERFACE_LINK_LIBRARIES "")

# meshoptimizer simplifies the as-printed skin to a tolerance (quadric edge collapse, sim/skin.cpp): a small,
# well-kept library that does this better than code of our own would.
find_package(meshoptimizer CONFIG REQUIRED)

# MPI (Open MPI from Debian, which tools/setup.sh installs) for sweeps across machines (tools/CMakeLists.txt):
# optional; without it `beadtwin sweep` runs on this machine only.
option(BEADTWIN_MPI "Build beadtwin sweep with MPI when MPI is installed" ON)
if(BEADTWIN_MPI AND NOT BEADTWIN_READERS_ONLY)
  find_package(MPI COMPONENTS CXX)
endif()
