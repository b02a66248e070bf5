// One part's heat transfer shared among the ranks of an MPI job (HeatOptions::communicator,
// thermal/heat.hpp): run by ctest under `mpirun -n 2`. Each rank also solves the same part alone; the shared
// solve must give the one-rank answer within what the solver's own tolerance moves it (the one-rank solve
// against one at a ten times tighter tolerance), and every rank must hold the same result.
#include <mpi.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <thread>
#include <vector>

#include "tests/thermal/test_meshes.hpp"
#include "thermal/heat.hpp"
#include "thermal/mpi/mpi_communicator.hpp"

namespace beadtwin::thermal {
namespace {

std::unique_ptr<Communicator> world;

// The largest difference of a field of the interfaces, the final temperatures and the layers' histories.
struct Differences {
  double substrate_k = 0.0, healing = 0.0, final_k = 0.0, history_k = 0.0;
};
Differences compare(const HeatResult& a, const HeatResult& b) {
  Differences d;
  EXPECT_EQ(a.interfaces.size(), b.interfaces.size());
  for (std::size_t k = 0; k < std::min(a.interfaces.size(), b.interfaces.size()); ++k) {
    d.substrate_k =
        std::max(d.substrate_k, std::abs(a.interfaces[k].substrate_c - b.interfaces[k].substrate_c));
    d.healing = std::max(d.healing, std::abs(a.interfaces[k].healing - b.interfaces[k].healing));
  }
  EXPECT_EQ(a.final_temp_c.size(), b.final_temp_c.size());
  for (std::size_t i = 0; i < std::min(a.final_temp_c.size(), b.final_temp_c.size()); ++i)
    d.final_k = std::max(d.final_k, static_cast<double>(std::abs(a.final_temp_c[i] - b.final_temp_c[i])));
  EXPECT_EQ(a.sample_times_s, b.sample_times_s);
  for (std::size_t l = 0; l < a.layer_temp_c.size(); ++l)
    for (std::size_t s = 0; s < std::min(a.layer_temp_c[l].size(), b.layer_temp_c[l].size()); ++s)
      if (!std::isnan(a.layer_temp_c[l][s]))
        d.history_k =
            std::max(d.history_k, static_cast<double>(std::abs(a.layer_temp_c[l][s] - b.layer_temp_c[l][s])));
  return d;
}

// Every rank's result is the same: rank 0's final temperatures and healing integrals, sent to all, equal
// each rank's own to the last bit.
void expect_same_on_every_rank(const HeatResult& r) {
  std::vector<double> mine(r.final_temp_c.begin(), r.final_temp_c.end());
  for (const InterfaceResult& i : r.interfaces) mine.push_back(i.healing_integral);
  std::vector<double> first = mine;
  MPI_Bcast(first.data(), static_cast<int>(first.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  EXPECT_EQ(mine, first) << "rank " << world->rank();
}

void expect_shared_equals_alone(const ThermalMesh& mesh, std::size_t layers, const Material& material,
                                const Environment& env, HeatOptions options) {
  const double end_s = mesh.cells.back().birth_s;
  const HeatResult alone = solve_heat(mesh, layers, end_s, material, env, options);
  HeatOptions tight = options;
  tight.rel_tol = options.rel_tol / 10.0;
  tight.abs_tol_k = options.abs_tol_k / 10.0;
  const HeatResult reference = solve_heat(mesh, layers, end_s, material, env, tight);
  options.communicator = world.get();
  const HeatResult shared = solve_heat(mesh, layers, end_s, material, env, options);

  EXPECT_EQ(alone.ranks, 1);
  EXPECT_EQ(shared.ranks, world->size());
  EXPECT_EQ(shared.birth_events, alone.birth_events);
  EXPECT_EQ(shared.lump_events, alone.lump_events);
  expect_same_on_every_rank(shared);
  const Differences tolerance = compare(alone, reference);
  const Differences across = compare(alone, shared);
  if (world->rank() == 0) {
    ::testing::Test::RecordProperty("substrate_K_tolerance", std::to_string(tolerance.substrate_k));
    ::testing::Test::RecordProperty("substrate_K_ranks", std::to_string(across.substrate_k));
    ::testing::Test::RecordProperty("healing_tolerance", std::to_string(tolerance.healing));
    ::testing::Test::RecordProperty("healing_ranks", std::to_string(across.healing));
    ::testing::Test::RecordProperty("final_K_ranks", std::to_string(across.final_k));
  }
  EXPECT_LE(across.substrate_k, std::max(tolerance.substrate_k, 0.05));
  EXPECT_LE(across.healing, std::max(tolerance.healing, 1e-3));
  EXPECT_LE(across.final_k, std::max(tolerance.final_k, 0.05));
  EXPECT_LE(across.history_k, std::max(tolerance.history_k, 0.05));
  // The balance closes as well as on one rank: the ranks' shares of the energy lost add up.
  EXPECT_LT(shared.energy_balance_rel_error, std::max(2.0 * alone.energy_balance_rel_error, 1e-6));
  EXPECT_NEAR(shared.energy_lost_J, alone.energy_lost_J, 1e-3 * std::abs(alone.energy_lost_J));
  // Not a trivial run: the part cooled well below the deposition temperature.
  EXPECT_LT(alone.final_temp_c.back(), material.deposition_temp_c - 50.0);
}

TEST(HeatAcrossRanks, TheJobHasSeveralRanks) {
  EXPECT_GE(world->size(), 2) << "run under mpirun -n 2 (or more)";
}

// A block of 30 × 30 × 20 cells laid layer by layer: the integrator is rebuilt as the part grows, and each
// rebuild shares the cells out again.
TEST(HeatAcrossRanks, ABlockLaidLayerByLayerGivesTheOneRankAnswer) {
  auto [material, env, options] = block_print();
  options.lump = false;
  expect_shared_equals_alone(block(30, 30, 20), 20, material, env, options);
}

// The same with settled cells lumped: every rank lumps the same cells, and the blocks follow the new cells.
TEST(HeatAcrossRanks, SettledCellsAreLumpedAlikeOnEveryRank) {
  auto [material, env, options] = thin_wall_print();
  const ThermalMesh mesh = thin_wall();
  expect_shared_equals_alone(mesh, 40, material, env, options);
  options.communicator = world.get();
  const HeatResult shared = solve_heat(mesh, 40, mesh.cells.back().birth_s, material, env, options);
  EXPECT_GT(shared.lump_events, 0u);
  EXPECT_GT(shared.lumped_cells, mesh.cells.size() / 2);
}

}  // namespace
}  // namespace beadtwin::thermal

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ::testing::InitGoogleTest(&argc, argv);
  if (rank != 0) {  // one report, rank 0's; a failure on any rank fails the job
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int failed = 0;
  {
    // The ranks share the machine's cores.
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                      std::max<std::size_t>(1, cores / static_cast<unsigned>(size)));
    beadtwin::thermal::world = beadtwin::thermal::world_communicator();
    failed = RUN_ALL_TESTS();
    beadtwin::thermal::world.reset();
  }
  int any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return any;
}
