// Mesh generation time and size per refinement level, for the paper's pinion (5-tooth sector):
// 2D (uncrowned) and 3D (crowned, beta = 80 um). Next to the time, each run reports what it
// bought: elements, nodes, the minimum scaled Jacobian and the measured edge length in the
// contact band.
//   build/bench/bench_meshing --benchmark_counters_tabular=true
#include "meshing/gear_body_mesher.h"
#include "meshing/pair_kinematics.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

using namespace hertzgear::meshing;

namespace
{
  PairKinematics paper_pair(const double crowning_mm)
  {
    PairParameters p;
    for (GearParameters *g : {&p.pinion, &p.gear})
      {
        g->module_mm          = 3;
        g->pressure_angle_rad = 20 * M_PI / 180;
        g->face_width_mm      = 20;
        g->crowning_mm        = crowning_mm;
      }
    p.pinion.teeth = 23, p.pinion.bore_radius_mm = 15, p.pinion.name = "pinion";
    p.pinion.tip_radius_mm = 37.337;
    p.gear.teeth = 34, p.gear.bore_radius_mm = 20, p.gear.name = "gear";
    p.gear.tip_radius_mm = 53.837;
    p.backlash_loa_mm = 0.1172;
    return PairKinematics(p);
  }

  void mesh_pinion(benchmark::State &state)
  {
    const int      dim   = int(state.range(0));
    const int      level = int(state.range(1));
    const auto     pair  = paper_pair(dim == 3 ? 0.08 : 0.0);
    MeshSettings   settings;
    settings.dimension        = dim;
    settings.refinement_level = level;
    const auto file = std::filesystem::temp_directory_path() / "hertzgear_bench_pinion.msh";
    MeshQuality q;
    GearBodyMesher mesher;
    for (auto _ : state)
      q = mesher.mesh(pair.pinion(), settings, pair.point('A').radius_pinion_mm, file);
    std::filesystem::remove(file);
    state.counters["elements"]       = double(q.n_elements);
    state.counters["nodes"]          = double(q.n_nodes);
    state.counters["min_scaled_jac"] = q.min_scaled_jacobian;
    state.counters["band_edge_mm"]   = q.contact_band_max_edge_mm;
    state.counters["flank_err_mm"]   = q.max_flank_modification_error_mm;
  }
} // namespace

BENCHMARK(mesh_pinion)
  ->ArgNames({"dim", "level"})
  ->Args({2, 0})->Args({2, 1})->Args({2, 2})->Args({2, 3})
  ->Args({3, 0})->Args({3, 1})
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

BENCHMARK_MAIN();
