#pragma once
// Pieces shared by the dynamics commands (dynamics, sweep, accuracy dynamics).
#include "app/command.h"
#include "app/dynamics_setup.h"

#include <nlohmann/json.hpp>

namespace hertzgear
{
  nlohmann::json integrator_json(const dynamics::IntegratorStats &stats);
  nlohmann::json summary_json(const DynamicsSetup &setup, const dynamics::GearPairModel &model,
                              const dynamics::SimulationResult &result,
                              const dynamics::SteadyStateSummary &summary);
  int run_accuracy_dynamics(const CommandContext &ctx);
} // namespace hertzgear
