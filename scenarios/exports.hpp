// The files a variant's run writes into its folder besides its pictures: the print program, the deposit
// (OpenVDB), the as-printed skin (a mesh), the voxel fields and the temperature snapshots (ParaView). Each
// writes into `dir` (the variant's folder) and records, in `files` or the result, the file's path relative
// to the run's folder (the variant's name / the file) and what the report says of it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/toolpath.hpp"
#include "scenarios/input/result.hpp"
#include "sim/deposit.hpp"
#include "sim/skin.hpp"
#include "thermal/thermal.hpp"

namespace beadtwin::scenarios {

// `toolpath` as the variant's print program: in its machine's dialect, headed with the scenario's and the
// variant's names.
std::string program_text(const Scenario& scenario, const Variant& variant, const Toolpath& toolpath);

// program.nc: program_text. Returns its path relative to the run's folder.
std::string write_program(const Scenario& scenario, const Variant& variant, const Toolpath& toolpath,
                          const std::filesystem::path& dir);

// deposit.vdb: the deposit's grids. Sets result.deposit_file and result.exported.deposit_bytes.
void write_deposit(const Variant& variant, const sim::Deposit& deposit, const std::filesystem::path& dir,
                   VariantResult& result);

// skin.ply or skin.stl (output.skin_format): the as-printed skin, simplified within
// output.skin_tolerance (mm), with the size of a bead-by-bead STL of the same print for comparison. Meshed
// from `surface` when given (the fill grid meshed at the skin's adaptivity), else here. When simplifying
// leaves no triangles, writes nothing and says why in `notes`.
void write_skin(const Variant& variant, const Toolpath& toolpath, const sim::Deposit& deposit,
                const sim::FillSurface* surface, const std::filesystem::path& dir, ExportedFiles& files,
                std::vector<std::string>& notes);

// fields.vtu: the deposit's voxel fields for ParaView.
void write_fields(const Variant& variant, const sim::Deposit& deposit, const std::filesystem::path& dir,
                  ExportedFiles& files);

// temperature-<t>s.vdb and .vtp for each snapshot the scenario asked for (thermal.snapshots; the snapshots
// taken for pictures only are not written).
void write_snapshots(const Variant& variant, const thermal::ThermalResult& thermal,
                     const std::filesystem::path& dir, ExportedFiles& files);

}  // namespace beadtwin::scenarios
