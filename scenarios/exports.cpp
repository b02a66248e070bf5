#include "scenarios/exports.hpp"

#include <algorithm>
#include <iterator>

#include <fmt/format.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "gcode/writer.hpp"
#include "scenarios/variant_stages.hpp"
#include "sim/deposit_files.hpp"
#include "thermal/snapshot_files.hpp"

namespace beadtwin::scenarios {

std::string program_text(const Scenario& sc, const Variant& v, const Toolpath& tp) {
  const gcode::GcodeHeader header{v.name, sc.name, v.name, v.machine.name, v.material.name};
  return gcode::write_gcode(tp, v.machine.dialect, header, gcode_options(v));
}

std::string write_program(const Scenario& sc, const Variant& v, const Toolpath& tp,
                          const std::filesystem::path& dir) {
  write_file_atomic(dir / "program.nc", program_text(sc, v, tp));
  return (std::filesystem::path(v.name) / "program.nc").string();
}

void write_deposit(const Variant& v, const sim::Deposit& deposit, const std::filesystem::path& dir,
                   VariantResult& res) {
  sim::write_deposit_vdb(deposit, dir / "deposit.vdb");
  res.deposit_file = (std::filesystem::path(v.name) / "deposit.vdb").string();
  res.exported.deposit_bytes = std::filesystem::file_size(dir / "deposit.vdb");
}

void write_skin(const Variant& v, const Toolpath& tp, const sim::Deposit& deposit,
                const sim::FillSurface* surface, const std::filesystem::path& dir, ExportedFiles& files,
                std::vector<std::string>& notes) {
  const auto* format =
      std::find_if(std::begin(sim::kMeshFormats), std::end(sim::kMeshFormats),
                   [&](sim::MeshFormat f) { return sim::to_string(f) == v.output.skin_format; });
  BT_CHECK(format != std::end(sim::kMeshFormats));  // the loader accepts only these
  const std::string name = "skin." + v.output.skin_format;
  const sim::SkinMesh skin =
      surface ? sim::extract_skin(*surface, true, v.output.skin_tolerance_mm)
              : sim::extract_skin(deposit, v.output.skin_adaptivity, true, v.output.skin_tolerance_mm);
  if (skin.triangles.empty()) {
    // Simplified away: beads no thicker than the tolerance (a desktop bead against the 0.3 mm default).
    notes.push_back(
        fmt::format("no skin written: simplified to within output.skin_tolerance = {:.3g} mm, the "
                    "part's surface left no triangles (its beads are about that thin); a smaller "
                    "tolerance, or 0, keeps them",
                    v.output.skin_tolerance_mm));
    return;
  }
  sim::write_mesh(skin, dir / name, *format);
  files.skin = (std::filesystem::path(v.name) / name).string();
  files.skin_bytes = std::filesystem::file_size(dir / name);
  files.skin_triangles = skin.triangles.size();
  const sim::BeadStlEstimate beads = sim::bead_by_bead_stl(tp);
  files.bead_stl_triangles = beads.triangles;
  files.bead_stl_bytes = beads.bytes;
}

void write_fields(const Variant& v, const sim::Deposit& deposit, const std::filesystem::path& dir,
                  ExportedFiles& files) {
  files.fields_cells = sim::write_deposit_vtu(deposit, dir / "fields.vtu").cells;
  files.fields = (std::filesystem::path(v.name) / "fields.vtu").string();
  files.fields_bytes = std::filesystem::file_size(dir / "fields.vtu");
}

void write_snapshots(const Variant& v, const thermal::ThermalResult& th, const std::filesystem::path& dir,
                     ExportedFiles& files) {
  for (const thermal::TemperatureSnapshot& s : th.heat.snapshots) {
    if (s.request >= v.thermal.snapshot_times_s.size()) continue;  // taken for a picture only
    const std::string stem = fmt::format("temperature-{:.0f}s", s.time_s);
    thermal::write_temperature_vdb(th.mesh, s, dir / (stem + ".vdb"));
    thermal::write_temperature_vtp(th.mesh, s, dir / (stem + ".vtp"));
    const std::filesystem::path rel(v.name);
    files.snapshots.push_back({s.time_s, (rel / (stem + ".vdb")).string(), (rel / (stem + ".vtp")).string()});
  }
}

}  // namespace beadtwin::scenarios
