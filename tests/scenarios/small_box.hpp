// The small scenario several tests run end to end in a few seconds: a 240 x 180 x 30 mm open box at LSAM
// scale in two sections (a floor of 10 mm with fill, walls of two passes), 2.5 mm voxels, 160 x 100
// pictures. Without variants or gates: each test adds its own after it.
#pragma once

#include <string>
#include <string_view>

namespace beadtwin::testing {

// The scenario named `name`, with `output` as its output block.
inline std::string small_box(std::string_view name, std::string_view output = "{voxel_size: 2.5 mm}") {
  return "name: " + std::string(name) + "\n" + R"(units: {length: mm}
machine: lsam-ph15
material: cf-abs-20
part:
  open_box: {size: [240, 180, 30], wall: 40, floor: 10}
output: )" +
         std::string(output) +
         R"(
render: {width: 160, height: 100}
sections:
  - {name: floor, z: [0, 10], layer_height: 5, bead_width: 20, boundary: {passes: 2}, fill: {angle: 45 deg}}
  - {name: walls, z: [10, 30], layer_height: 5, bead_width: 20, boundary: {passes: 2}, fill: none}
)";
}

}  // namespace beadtwin::testing
