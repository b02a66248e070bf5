// The declarations of a scenario's parameters (core/param.hpp): one per key, bound to the member it sets.
// A section's are the slicer's (slicer::section_params); the rest are declared here, beside nothing else:
// the scenario reader reads every block through them, `beadtwin params` and docs/parameters.md print them,
// and the report lists a variant's parameters from them.
#pragma once

#include <span>
#include <string>

#include "core/material.hpp"
#include "core/param.hpp"
#include "scenarios/input/scenario.hpp"

namespace beadtwin::scenarios {

// The keys of each block of a scenario and of the machine and material files. Declarations without a
// member are read by their block's own code (scenarios/input/scenario.cpp), which says how.
std::span<const Param<Scenario>> scenario_params();  // the top level of a scenario file
std::span<const Param<Machine>> machine_params();
std::span<const Param<Material>> material_params();
std::span<const Param<PartSpec>> part_params();
std::span<const Param<Tool>> tool_params();
std::span<const Param<OutputSpec>> output_params();
std::span<const Param<ThermalSpec>> thermal_params();
std::span<const Param<RenderSpec>> render_params();
std::span<const Param<ImageSpec>> image_params();
std::span<const Param<render::CameraSpec>> camera_params();  // an image's or the progress frames' view
std::span<const Param<ProgressSpec>> progress_params();

// Every parameter table as Markdown: what `beadtwin params` prints and docs/parameters.md holds.
std::string params_markdown();

}  // namespace beadtwin::scenarios
