// Tests of the thermal mesh (thermal/mesh.hpp) built from real deposits of straight LSAM beads: what the
// control volumes hold (volume, birth, strips) and what their faces are (contacts between beads, open
// surface, the table), each against the bead's geometry.
//
// Geometry used throughout: the flattened bead is the stadium of sim/deposit.hpp, w = 0.83 in, h = 0.2 in,
// section A = h (w − h) + π h²/4, flat top and bottom of width w − h, semicircular sides of radius h/2. The
// voxel size is h/10 so that layers start and end on voxel rows, and the beads run along x from x = 0 on the
// line y = 0 (a voxel boundary), so that the voxels lie symmetrically about it.
#include "thermal/mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "tests/sim/lsam_beads.hpp"

namespace beadtwin::thermal {
namespace {

using testing::bead;
using testing::kBeadHeight;
using testing::kBeadWidth;
using testing::timed;
using testing::travel;

constexpr double kVoxel = kBeadHeight / 10.0;  // 0.508 mm
// Beads end on a voxel boundary: where a bead ends inside a voxel column, the deposit lets the material of a
// bead laid on it run down through the lower bead's partly filled end voxels to the table, which would blur
// the contacts checked here.
constexpr double kLength = 590 * kVoxel;  // 299.72 mm

std::string sci(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3e", value);
  return text;
}

double relative_error(double value, double reference) {
  return std::abs(value - reference) / std::abs(reference);
}

sim::Deposit deposit_of(const Toolpath& toolpath, double voxel_mm = kVoxel) {
  sim::DepositOptions options;
  options.voxel_size_mm = voxel_mm;
  return sim::deposit(toolpath, options);
}

// One bead of kLength along x on the table.
Toolpath single_bead() {
  return timed({bead({0.0, 0.0, kBeadHeight}, {kLength, 0.0, kBeadHeight})});
}

// Two beads of kLength along x, the second laid on the first, both from x = 0.
Toolpath stacked_beads() {
  const double z0 = kBeadHeight, z1 = 2.0 * kBeadHeight;
  return timed({bead({0.0, 0.0, z0}, {kLength, 0.0, z0}, 0), travel({kLength, 0.0, z0}, {0.0, 0.0, z1}),
                bead({0.0, 0.0, z1}, {kLength, 0.0, z1}, 1)});
}

// `count` beads side by side at the pitch that fills the layer (A / h), `layers` high, with travels.
Toolpath block(int count, int layers) {
  return testing::bead_block(count, layers, 100.0);
}

// The mean width, over the voxel row [0, s] at a flat face of the stadium, of the section's semicircular
// sides (both together): (2 / s) ∫₀^s √(r² − (r − z)²) dz with r = h/2. A voxel row resting on the table (or
// on a bead below) holds the flat part w − h and this much of the rounded flanks besides, so the table
// area and the contact between stacked beads are (w − h + this) × L on the voxels; it tends to 0 as
// (4/3) √(2 r s) when the voxel shrinks (1.9 mm of 16.0 mm here, 4.0 mm at the default voxel h/2).
double flank_width_in_row_mm(double s) {
  const double r = 0.5 * kBeadHeight;
  const double u = r - s;
  const double below = 0.5 * (u * std::sqrt(r * r - u * u) + r * r * std::asin(u / r));  // ∫₀^u √(r² − x²)
  return 2.0 * (0.25 * kPi * r * r - below) / s;
}

// ---- volumes ---------------------------------------------------------------------------------------------

TEST(ThermalMeshTest, CellVolumesAddUpToTheDeposit) {
  // Three beads side by side, two layers: beads that meet, material pushed between them, a second layer.
  const Toolpath toolpath = block(3, 2);
  const sim::Deposit deposit = deposit_of(toolpath, kBeadHeight / 4.0);
  const ThermalMesh mesh = build_thermal_mesh(toolpath, deposit);
  ASSERT_FALSE(mesh.cells.empty());
  EXPECT_EQ(mesh.chains, 6u);
  double volume = 0.0;
  for (const ThermalCell& c : mesh.cells) {
    EXPECT_GT(c.volume_mm3, 0.0);
    volume += c.volume_mm3;
  }
  RecordProperty("volume_rel_error", sci(relative_error(volume, deposit.deposited_volume_mm3)));
  EXPECT_LT(relative_error(volume, deposit.deposited_volume_mm3), 1e-9);  // the same sum, in another order

  // Every material voxel belongs to a cell; cells come by birth, links by (a, b) with a < b.
  ASSERT_TRUE(mesh.cell_grid);
  EXPECT_EQ(mesh.cell_grid->activeVoxelCount(), deposit.fill->activeVoxelCount());
  for (auto it = mesh.cell_grid->cbeginValueOn(); it; ++it) {
    ASSERT_GE(*it, 0);
    ASSERT_LT(static_cast<std::size_t>(*it), mesh.cells.size());
  }
  for (std::size_t i = 1; i < mesh.cells.size(); ++i)
    EXPECT_LE(mesh.cells[i - 1].birth_s, mesh.cells[i].birth_s);
  // Each bead here is one move and a chain of its own: contacts between beads are interfaces, contacts
  // inside one are not.
  for (std::size_t l = 0; l < mesh.links.size(); ++l) {
    EXPECT_LT(mesh.links[l].a, mesh.links[l].b);
    EXPECT_EQ(mesh.links[l].interface, mesh.cells[mesh.links[l].a].move != mesh.cells[mesh.links[l].b].move);
    if (l > 0) {
      EXPECT_LT(std::make_pair(mesh.links[l - 1].a, mesh.links[l - 1].b),
                std::make_pair(mesh.links[l].a, mesh.links[l].b));
    }
  }
}

// ---- one bead --------------------------------------------------------------------------------------------

TEST(ThermalMeshTest, SingleBeadIsCutIntoPiecesAndThreeStrips) {
  const Toolpath toolpath = single_bead();
  const sim::Deposit deposit = deposit_of(toolpath);
  const ThermalMesh mesh = build_thermal_mesh(toolpath, deposit);  // 3 across, 1 through, 2 widths long
  // Pieces of about two bead widths: round(299.72 / 42.16) = 7.
  const auto pieces = static_cast<std::size_t>(std::lround(kLength / (2.0 * kBeadWidth)));
  ASSERT_EQ(pieces, 7u);
  EXPECT_EQ(mesh.chains, 1u);
  ASSERT_EQ(mesh.cells.size(), 3 * pieces);

  // Strips by the centroid's side of the bead; pieces by the centroid along it.
  std::map<int, std::vector<const ThermalCell*>> strips;
  for (const ThermalCell& c : mesh.cells) {
    const int strip = c.centroid_mm.y() < -0.25 * kBeadWidth  ? 0
                      : c.centroid_mm.y() > 0.25 * kBeadWidth ? 2
                                                              : 1;
    strips[strip].push_back(&c);
    EXPECT_EQ(c.layer, 0);
    EXPECT_EQ(c.move, 0u);
    EXPECT_NEAR(std::abs(c.along.x()), 1.0, 1e-9);  // the bead runs along x
  }
  ASSERT_EQ(strips.size(), 3u);
  for (auto& [strip, cells] : strips) {
    ASSERT_EQ(cells.size(), pieces) << "strip " << strip;
    std::sort(cells.begin(), cells.end(), [](const ThermalCell* a, const ThermalCell* b) {
      return a->centroid_mm.x() < b->centroid_mm.x();
    });
  }

  // Strips are a third of the bead's width each: the centre one is all flat part (w/3 < w − h), h × w/3 in
  // section; the edges share the rest of A. Pieces are a seventh of the length. A cell takes the voxels
  // whose centres lie in it, so on the voxels the centre strip is as wide as the voxel columns whose centres
  // lie within ±w/6 (14 columns, 7.11 mm for 7.03 mm) and a piece as long as its voxel slices (84 or 85).
  // With that quantisation the volumes are exact but for the deposit's scaling of the swept fill to the
  // commanded volume: 0.5 % tolerance.
  const double area = bead_area_mm2(kBeadWidth, kBeadHeight);
  const double piece_mm = kLength / static_cast<double>(pieces);
  const auto voxel_span_mm = [](double from, double to) {  // the voxels with centres in [from, to)
    return kVoxel * (std::ceil(to / kVoxel - 0.5) - std::ceil(from / kVoxel - 0.5));
  };
  const double centre_width_mm = voxel_span_mm(-kBeadWidth / 6.0, kBeadWidth / 6.0);
  ASSERT_NEAR(centre_width_mm, 14 * kVoxel, 1e-9);
  double worst_centre = 0.0, worst_edge = 0.0, worst_symmetry = 0.0;
  for (std::size_t p = 0; p < pieces; ++p) {
    const ThermalCell& left = *strips[0][p];
    const ThermalCell& centre = *strips[1][p];
    const ThermalCell& right = *strips[2][p];
    const double length_mm =
        voxel_span_mm(static_cast<double>(p) * piece_mm, static_cast<double>(p + 1) * piece_mm);
    const double centre_mm3 = kBeadHeight * centre_width_mm * length_mm;
    const double edge_mm3 = 0.5 * (area * length_mm - centre_mm3);
    worst_centre = std::max(worst_centre, relative_error(centre.volume_mm3, centre_mm3));
    worst_edge = std::max(
        {worst_edge, relative_error(left.volume_mm3, edge_mm3), relative_error(right.volume_mm3, edge_mm3)});
    // The two edges mirror each other about the bead's axis, which is a voxel boundary; the deposit's
    // supersampled fill is itself mirror-symmetric to about 1e-4 (its two halves differ by 8e-5).
    worst_symmetry = std::max(worst_symmetry, relative_error(left.volume_mm3, right.volume_mm3));
    EXPECT_NEAR(left.centroid_mm.y(), -right.centroid_mm.y(), 0.01 * kVoxel);
    EXPECT_NEAR(centre.centroid_mm.y(), 0.0, 0.01 * kVoxel);
    // Each piece is a seventh of the bead.
    EXPECT_NEAR(centre.centroid_mm.x(), (static_cast<double>(p) + 0.5) * piece_mm, kVoxel);
  }
  RecordProperty("centre_strip_volume_error", sci(worst_centre));
  RecordProperty("edge_strip_volume_error", sci(worst_edge));
  RecordProperty("edge_symmetry_error", sci(worst_symmetry));
  EXPECT_LT(worst_centre, 0.005);
  EXPECT_LT(worst_edge, 0.005);
  EXPECT_LT(worst_symmetry, 1e-3);

  // Birth times increase along the bead, and lie within the move's time.
  const Move& m = toolpath.moves[0];
  for (const auto& [strip, cells] : strips)
    for (std::size_t p = 0; p < pieces; ++p) {
      EXPECT_GT(cells[p]->birth_s, m.start_s);
      EXPECT_LT(cells[p]->birth_s, m.start_s + m.duration_s);
      if (p > 0) {
        EXPECT_GT(cells[p]->birth_s, cells[p - 1]->birth_s) << "strip " << strip << " piece " << p;
      }
    }
  // A piece's strips are born together (within one voxel's passage).
  for (std::size_t p = 0; p < pieces; ++p)
    EXPECT_NEAR(strips[0][p]->birth_s, strips[2][p]->birth_s, kVoxel / m.feed_mm_s);

  // No interface inside one bead.
  for (const ThermalLink& l : mesh.links) EXPECT_FALSE(l.interface) << l.a << "-" << l.b;
}

// The open surface of a bead alone on the table is its free perimeter — the flat top w − h and the two
// semicircular sides π h — times its length, plus its two square-cut ends (A each); the table area its flat
// bottom, (w − h) × L. On the voxels the row on the table also holds part of the rounded flanks
// (flank_width_in_row_mm: 12 % of the footprint at this voxel), which the table takes as contact and the open
// surface loses. With that accounted for, what is left is how voxels represent a curved face: 1 % on the
// table (the supersampled fill of the flank voxels; measured 0.03 %), 2 % on the open surface (each voxel's
// faces summed as a vector are exact for a plane but not where the surface turns within the voxel, as it does
// all round the semicircles, 5 voxels in radius; measured 0.7 %).
TEST(ThermalMeshTest, AnAutomaticCellLengthIsMadeLongerWhenItWouldMakeTooManyCells) {
  // 299.72 / 42.16 = 7.11 pieces of two bead widths, three strips: 21.3 cells. Allowed 9, the pieces are
  // made 21.3 / 9 = 2.37 times longer: round(299.72 / (42.16 * 2.37)) = 3 pieces, 9 cells. A length asked
  // for is kept.
  const Toolpath toolpath = single_bead();
  const sim::Deposit deposit = deposit_of(toolpath);
  MeshOptions o;
  o.max_automatic_cells = 9;
  const ThermalMesh mesh = build_thermal_mesh(toolpath, deposit, o);
  EXPECT_NEAR(mesh.cell_length_factor, kLength / (2.0 * kBeadWidth) * 3.0 / 9.0, 1e-12);
  EXPECT_EQ(mesh.cells.size(), 9u);
  EXPECT_EQ(planned_cell_count(toolpath, o), mesh.cells.size());  // known before the deposit's voxels
  // The note gives the count there would have been as a count (21), not as "2.13e-05 million".
  ASSERT_EQ(mesh.notes.size(), 1u);
  EXPECT_NE(mesh.notes[0].find("there would be about 21, too many"), std::string::npos) << mesh.notes[0];
  o.cell_length_mm = 2.0 * kBeadWidth;
  const ThermalMesh asked = build_thermal_mesh(toolpath, deposit, o);
  EXPECT_EQ(asked.cell_length_factor, 1.0);
  EXPECT_EQ(asked.cells.size(), 21u);
  EXPECT_EQ(planned_cell_count(toolpath, o), asked.cells.size());
  EXPECT_EQ(build_thermal_mesh(toolpath, deposit).cell_length_factor, 1.0);  // 21 cells are few
}

// What the thermal stage holds: 3,000 bytes a planned cell, and a grid as large as the deposit's layer grid.
TEST(ThermalMeshTest, CostIsItsPlannedCellsAndACellGrid) {
  const Toolpath toolpath = single_bead();
  const sim::Deposit deposit = deposit_of(toolpath);
  const MemoryCost cost = thermal_cost(toolpath, deposit);
  EXPECT_DOUBLE_EQ(cost.fixed_bytes, 3000.0 * static_cast<double>(planned_cell_count(toolpath)));
  EXPECT_GT(cost.fixed_bytes, 0.0);
  EXPECT_DOUBLE_EQ(cost.volume_bytes, static_cast<double>(deposit.layer->memUsage()));
  EXPECT_EQ(cost.surface_bytes, 0.0);
  EXPECT_EQ(thermal_cost(toolpath, sim::Deposit{}).volume_bytes, 0.0);
}

TEST(ThermalMeshTest, SingleBeadOpenAreaIsItsFreePerimeterAndTableAreaItsFootprint) {
  const Toolpath toolpath = single_bead();
  const sim::Deposit deposit = deposit_of(toolpath);
  const ThermalMesh mesh = build_thermal_mesh(toolpath, deposit);
  double open = 0.0, table = 0.0;
  for (const ThermalCell& c : mesh.cells) {
    open += c.open_area_mm2;
    table += c.table_area_mm2;
  }
  const double w = kBeadWidth, h = kBeadHeight, area = bead_area_mm2(w, h);
  const double flank = flank_width_in_row_mm(kVoxel);
  const double footprint = (w - h) * kLength;
  const double table_voxels = (w - h + flank) * kLength;
  const double free_surface = ((w - h) + kPi * h) * kLength + 2.0 * area;
  const double open_voxels = free_surface - flank * kLength;
  std::printf("single bead: table %.0f mm² (footprint %.0f, on the voxels %.0f)\n", table, footprint,
              table_voxels);
  std::printf("single bead: open %.0f mm² (free surface %.0f, on the voxels %.0f)\n", open, free_surface,
              open_voxels);
  RecordProperty("table_error_voxel_model", sci(relative_error(table, table_voxels)));
  RecordProperty("table_over_footprint", sci(table / footprint - 1.0));
  RecordProperty("open_error_voxel_model", sci(relative_error(open, open_voxels)));
  RecordProperty("open_over_free_surface", sci(open / free_surface - 1.0));
  EXPECT_LT(relative_error(table, table_voxels), 0.01);
  EXPECT_LT(relative_error(open, open_voxels), 0.02);
  // Against the bead itself: the table holds the footprint and the flanks in the bottom row, the open
  // surface the rest.
  EXPECT_GT(table, footprint);
  EXPECT_LT(open, free_surface);
  EXPECT_LT(relative_error(table + open, free_surface + footprint), 0.02);
  EXPECT_NEAR(mesh.table_z_mm, 0.0, 1e-9);
  // The centre strip does not reach the air at the sides: its open surface is its top and its two ends.
  for (const ThermalCell& c : mesh.cells) {
    if (std::abs(c.centroid_mm.y()) > 0.25 * w) continue;
    const double piece_mm = kLength / 7.0;
    const bool end = c.centroid_mm.x() < piece_mm || c.centroid_mm.x() > kLength - piece_mm;
    const double expected = w / 3.0 * piece_mm + (end ? h * w / 3.0 : 0.0);
    EXPECT_LT(relative_error(c.open_area_mm2, expected), kVoxel / (w / 3.0)) << c.centroid_mm.x();
  }
}

// The half cell behind the open surface (ThermalCell::open_depth_mm3): the centre strip's top lies half the
// bead's height above its centroid, through the layer; an edge strip's rounded flank lies, on average over
// its area, about a third of the bead width out from the strip's centroid, across the bead, and nothing
// faces along the bead away from the ends. Within a voxel (the surface is placed by the voxels' fill).
TEST(ThermalMeshTest, SingleBeadHalfCellsReachFromTheCentroidToTheOpenFaces) {
  const Toolpath toolpath = single_bead();
  const sim::Deposit deposit = deposit_of(toolpath);
  const ThermalMesh mesh = build_thermal_mesh(toolpath, deposit);
  const double w = kBeadWidth, h = kBeadHeight, piece_mm = kLength / 7.0;
  int centre = 0, edge = 0;
  for (const ThermalCell& c : mesh.cells) {
    if (c.centroid_mm.x() < piece_mm || c.centroid_mm.x() > kLength - piece_mm) continue;  // ends
    const Eigen::Vector3d depth = c.open_depth_mm3 / c.open_area_mm2;  // area-weighted depth × n²
    EXPECT_LT(depth.x(), 0.01) << "nothing open along the bead (mm)";
    if (std::abs(c.centroid_mm.y()) < 0.25 * w) {
      ++centre;
      EXPECT_NEAR(depth.z(), h - c.centroid_mm.z(), 0.5 * kVoxel);
      EXPECT_NEAR(c.centroid_mm.z(), 0.5 * h, 0.5 * kVoxel);
      EXPECT_LT(depth.y(), 0.01);
    } else {
      ++edge;
      const double across = depth.y() + depth.z();  // the flank faces sideways and up
      EXPECT_GT(across, 0.1 * w / 3.0);
      EXPECT_LT(across, w / 3.0);
    }
  }
  EXPECT_EQ(centre, 5);
  EXPECT_EQ(edge, 10);
}

// ---- two beads -------------------------------------------------------------------------------------------

// The second bead lies on the first: every contact between them is an interface (another chain), from the
// older, lower cell to the younger, facing up; together the contacts cover the flat top of the first bead,
// (w − h) × L, and on the voxels the flanks that the two rows meeting there hold (flank_width_in_row_mm, as
// on the table): within 1 % of (w − h + flank) × L (measured 0.2 %), 13 % above (w − h) × L.
//
// Not exactly +z: a voxel belongs to the move that last put material in it, so the few top-row voxels of the
// lower bead's flanks that the upper bead topped up belong to the upper bead's edge strips, and their sides
// touch the lower bead. That tilts each edge-strip contact by up to about 7° (towards ±y, mirror images on
// the two sides), and where such a voxel sits at a piece boundary it touches the next piece of the lower bead
// through one partly filled side face: a sliver of under a voxel face (0.26 mm²) facing along the bead. The
// centre strip's contacts are exactly vertical.
TEST(ThermalMeshTest, StackedBeadsMeetAtAnInterfaceFacingUp) {
  const Toolpath toolpath = stacked_beads();
  const sim::Deposit deposit = deposit_of(toolpath);
  const ThermalMesh mesh = build_thermal_mesh(toolpath, deposit);
  EXPECT_EQ(mesh.chains, 2u);
  const double face_mm2 = kVoxel * kVoxel;
  double interface_area = 0.0, sliver_area = 0.0;
  Eigen::Vector3d interface_vector = Eigen::Vector3d::Zero();
  std::size_t contacts = 0;
  for (const ThermalLink& l : mesh.links) {
    const ThermalCell& a = mesh.cells[l.a];
    const ThermalCell& b = mesh.cells[l.b];
    if (a.layer == b.layer) {
      EXPECT_FALSE(l.interface) << "inside one bead: " << l.a << "-" << l.b;
      continue;
    }
    EXPECT_TRUE(l.interface);
    EXPECT_EQ(a.layer, 0);
    EXPECT_EQ(b.layer, 1);
    EXPECT_LT(a.birth_s, b.birth_s);
    interface_area += l.area_mm2();
    interface_vector += l.area_vector_mm2;
    const Eigen::Vector3d& v = l.area_vector_mm2;
    if (l.area_mm2() <= face_mm2) {
      sliver_area += l.area_mm2();
      continue;
    }
    ++contacts;
    EXPECT_GT(v.z(), std::cos(10.0 * kPi / 180.0) * v.norm()) << "not facing up: " << v.transpose();
    EXPECT_LT(std::abs(v.x()), 0.01 * v.norm()) << v.transpose();
    if (std::abs(a.centroid_mm.y()) < 0.25 * kBeadWidth) {
      EXPECT_EQ(v.head<2>().norm(), 0.0) << v.transpose();
    }
  }
  EXPECT_EQ(contacts, 21u);  // every strip of every piece on the one below it
  EXPECT_LT(sliver_area, 1e-3 * interface_area);
  const double w = kBeadWidth, h = kBeadHeight;
  const double contact = (w - h) * kLength;
  const double contact_voxels = (w - h + flank_width_in_row_mm(kVoxel)) * kLength;
  std::printf("stacked beads: interface %.0f mm² (flat top %.0f, on the voxels %.0f)\n", interface_area,
              contact, contact_voxels);
  RecordProperty("interface_error_voxel_model", sci(relative_error(interface_area, contact_voxels)));
  RecordProperty("interface_over_flat_top", sci(interface_area / contact - 1.0));
  EXPECT_LT(relative_error(interface_area, contact_voxels), 0.01);
  EXPECT_GT(interface_area, contact);
  // The tilts of the two sides cancel: as a whole the interface faces up.
  EXPECT_LT(interface_vector.head<2>().norm(), 1e-3 * interface_area);
  // The shared faces lie at the top of the lower bead: that is where each cell's half of a contact ends.
  for (const ThermalLink& l : mesh.links) {
    if (l.interface && l.area_mm2() > face_mm2 && std::abs(mesh.cells[l.a].centroid_mm.y()) < 0.25 * w) {
      EXPECT_NEAR(l.face_centroid_mm.z(), h, 1e-9);
    }
  }
}

// Beads side by side touch along their flanks, about a layer height by their length each, facing across:
// a voxel where a later bead tops up its neighbour's round corner stays the neighbour's (the deposit's move
// grid names the move whose material a voxel mostly is), so a bead's cells do not wrap round the corners
// of the one beside it. At the default voxel (half the layer height) and at a quarter of it, alike. (Given
// to the last bead to touch it, at four voxel rows per layer the contact came out about twice as large and
// mostly facing up.)
TEST(ThermalMeshTest, BeadsSideBySideShareTheirFlanksNotTheirCorners) {
  const Toolpath toolpath = block(3, 1);
  for (const double voxel : {0.5 * kBeadHeight, 0.25 * kBeadHeight}) {
    const sim::Deposit deposit = deposit_of(toolpath, voxel);
    const ThermalMesh mesh = build_thermal_mesh(toolpath, deposit);
    double area = 0.0, facing_up = 0.0;
    for (const ThermalLink& l : mesh.links) {
      if (!l.interface) continue;
      area += l.area_mm2();
      facing_up += std::abs(l.area_vector_mm2.z());
    }
    const double flanks = 2.0 * kBeadHeight * 100.0;  // two junctions, a layer height by the beads' length
    std::printf("voxel %.3f mm: beads side by side share %.0f mm² (flanks %.0f), %.0f mm² of it facing up\n",
                voxel, area, flanks, facing_up);
    EXPECT_GT(area, 0.6 * flanks) << "voxel " << voxel;
    EXPECT_LT(area, 1.15 * flanks) << "voxel " << voxel;
    EXPECT_LT(facing_up, 0.25 * area) << "voxel " << voxel;
  }
}

// ---- options ---------------------------------------------------------------------------------------------

TEST(ThermalMeshTest, BadOptionsAreInputErrorsNamingTheKey) {
  const Toolpath toolpath = single_bead();
  const sim::Deposit deposit = deposit_of(toolpath, kBeadHeight / 2.0);
  const auto key_of = [&](const MeshOptions& o) -> std::string {
    try {
      build_thermal_mesh(toolpath, deposit, o);
    } catch (const InputError& e) {
      return e.key();
    }
    return "(no error)";
  };
  for (const int across : {0, 2, 16, -1, 17}) {
    MeshOptions o;
    o.cells_across = across;
    EXPECT_EQ(key_of(o), "thermal.cells_across") << across;
  }
  for (const int through : {0, -1, 16}) {
    MeshOptions o;
    o.cells_through = through;
    EXPECT_EQ(key_of(o), "thermal.cells_through") << through;
  }
  MeshOptions o;
  o.cell_length_mm = -1.0;
  EXPECT_EQ(key_of(o), "thermal.cell_length");
  o.cell_length_mm = std::nan("");
  EXPECT_EQ(key_of(o), "thermal.cell_length");
  // The limits themselves are fine.
  o = {};
  o.cells_across = 15;
  o.cells_through = 15;
  EXPECT_EQ(key_of(o), "(no error)");
}

TEST(ThermalMeshTest, EmptyDepositGivesAnEmptyMesh) {
  const Toolpath toolpath;
  const sim::Deposit deposit = sim::deposit(toolpath);
  const ThermalMesh mesh = build_thermal_mesh(toolpath, deposit);
  EXPECT_TRUE(mesh.cells.empty());
  EXPECT_TRUE(mesh.links.empty());
}

}  // namespace
}  // namespace beadtwin::thermal
