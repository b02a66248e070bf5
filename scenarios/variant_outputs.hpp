// What a variant's run makes from its deposit besides the thermal stage: the deposit's files (deposit.vdb,
// the skin, the voxel fields) and the pictures. Most of it needs only the deposit, so the runner may make it
// on a thread beside the thermal stage (scenarios/beside.hpp) when the memory budget has room for it held
// through that stage, or after it; this class keeps the order either way and times each part as a stage.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>

#include "core/stages.hpp"
#include "scenarios/beside.hpp"
#include "scenarios/pictures.hpp"

namespace beadtwin::scenarios {

class VariantOutputs {
 public:
  // The outputs of the variant `in` describes (its deposit made), written into `dir` (the variant's folder)
  // and recorded in `result`; each part timed in `stages` (vdb, skin, fields, render). `beside_thermal`:
  // whether they are made beside the thermal stage; then the skin and the pictures of the whole part share
  // one meshing of the deposit's surface (when the skin is meshed at adaptivity 0, the default). What `in`
  // points to must outlive this object.
  VariantOutputs(PictureInputs in, std::filesystem::path dir, VariantResult& result, Stages& stages,
                 bool beside_thermal);
  ~VariantOutputs();
  VariantOutputs(const VariantOutputs&) = delete;
  VariantOutputs& operator=(const VariantOutputs&) = delete;

  // The deposit's files not yet written, each written once by whichever thread comes to it first.
  void write_files();
  // The pictures' shapes and the pictures that need no thermal result; `cad` is the CAD comparison (null
  // without one). Once, on any thread.
  void pictures_without_thermal(const CadCheck* cad);
  // The rest once the thermal stage is done: the pictures coloured by it (and those without, if not made
  // yet), then any file not yet written; the notes of both join the result's, and every part's time is
  // recorded.
  void finish(const thermal::ThermalResult& thermal, const CadCheck* cad);

 private:
  struct SharedSurface;
  PictureInputs in_;
  std::filesystem::path dir_;
  VariantResult& result_;
  Stages& stages_;
  bool share_surface_ = false;
  std::unique_ptr<SharedSurface> surface_;
  SharedJobs files_;
  std::optional<PictureWriter> pictures_;
  std::vector<std::string> skin_notes_;
};

}  // namespace beadtwin::scenarios
