#include "scenarios/variant_outputs.hpp"

#include <mutex>

#include "render/surface.hpp"
#include "scenarios/exports.hpp"
#include "sim/skin.hpp"

namespace beadtwin::scenarios {

// The fill grid's surface at adaptivity 0, meshed once for the skin and the pictures of the whole part by
// whichever comes to it first, and dropped once both are done with it.
struct VariantOutputs::SharedSurface {
  std::mutex mutex;
  bool made = false;
  std::optional<sim::FillSurface> mesh;
  int users = 2;  // the skin and the pictures
  // The surface, or null once both are done with it.
  const sim::FillSurface* get(const sim::Deposit& d) {
    const std::lock_guard lock(mutex);
    if (!made) mesh = sim::mesh_fill(d, 0.0), made = true;
    return mesh ? &*mesh : nullptr;
  }
  void done() {
    const std::lock_guard lock(mutex);
    if (--users == 0) mesh.reset();
  }
};

VariantOutputs::VariantOutputs(PictureInputs in, std::filesystem::path dir, VariantResult& result,
                               Stages& stages, bool beside_thermal)
    : in_(std::move(in)),
      dir_(std::move(dir)),
      result_(result),
      stages_(stages),
      surface_(std::make_unique<SharedSurface>()) {
  const Variant& v = *in_.variant;
  const sim::Deposit& deposit = *in_.deposit;
  // Without room beside the thermal stage each meshes its own, as the pictures' surfaces are then held
  // through it.
  share_surface_ = beside_thermal && !v.output.skin_format.empty() && v.output.skin_adaptivity == 0.0;
  in_.whole_surface = [this]() -> std::optional<render::SurfaceMesh> {
    if (!share_surface_) return std::nullopt;
    const openvdb::Index64 active = in_.deposit->fill->activeVoxelCount();
    const sim::FillSurface* s = active > 0 ? surface_->get(*in_.deposit) : nullptr;
    if (s == nullptr) return std::nullopt;  // the pictures say what is wrong themselves
    return render::surface_mesh(s->points_mm, s->triangles, s->quads, active);
  };
  // The skin before the pictures: its mesh is gone before the pictures' surfaces and scenes are built, which
  // lowers the run's peak (docs/PERFORMANCE.md).
  files_.add(
      [this, &v, &deposit] { stages_.run_aside("vdb", [&] { write_deposit(v, deposit, dir_, result_); }); });
  if (!v.output.skin_format.empty())
    files_.add([this, &v, &deposit] {
      stages_.run_aside("skin", [&] {
        const sim::FillSurface* surface = share_surface_ ? surface_->get(deposit) : nullptr;
        write_skin(v, *in_.toolpath, deposit, surface, dir_, result_.exported, skin_notes_);
        if (share_surface_) surface_->done();
      });
    });
  if (v.output.write_fields)
    files_.add([this, &v, &deposit] {
      stages_.run_aside("fields", [&] { write_fields(v, deposit, dir_, result_.exported); });
    });
}

VariantOutputs::~VariantOutputs() = default;

void VariantOutputs::write_files() {
  files_.work();
}

void VariantOutputs::pictures_without_thermal(const CadCheck* cad) {
  stages_.run_aside("render", [&] {
    in_.cad = cad;
    pictures_.emplace(in_, dir_);
    pictures_->without_thermal();
  });
  if (share_surface_) surface_->done();
}

void VariantOutputs::finish(const thermal::ThermalResult& thermal, const CadCheck* cad) {
  if (!pictures_) pictures_without_thermal(cad);
  PictureFiles files = stages_.run_aside(
      "render", [&] { return pictures_->finish(thermal); }, true);
  stages_.record_aside("render");
  const std::vector<std::string>& picture_notes = pictures_->notes();
  result_.notes.insert(result_.notes.end(), picture_notes.begin(), picture_notes.end());
  result_.images = std::move(files.images);
  result_.exr_images = std::move(files.exr);
  result_.progress_frames = std::move(files.progress);
  pictures_.reset();  // the shapes
  write_files();      // without room beside the thermal stage, all of them now, after the pictures
  for (const char* stage : {"vdb", "skin", "fields"}) stages_.record_aside(stage);  // those asked for
  result_.notes.insert(result_.notes.end(), skin_notes_.begin(), skin_notes_.end());
}

}  // namespace beadtwin::scenarios
