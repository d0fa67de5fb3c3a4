#pragma once
// The work of `napkin transform` as a function tests and `napkin demo` call.
#include <string>
#include <vector>

#include "engine/kinematics.h"
#include "engine/summary.h"

namespace napkin::app {

struct TransformOptions {
  std::string array;                         // preset name or array JSON path
  std::vector<double> orientation_rad;       // phi, theta, psi (empty: 0, 0, 0)
  std::vector<double> initial_velocity_mps;  // vx, vy, vz fixed frame (empty: 0)
  std::string solver;                        // engine::SolverName (empty: the config's solver)
  std::string config;                        // processing config preset/path (empty: default)
  std::string input;                         // signals file
  std::vector<std::string> csv_columns;      // --column SLOT=NAME
  std::string out;                           // derived-channel CSV
  std::string summary;                       // summary JSON (optional)
  std::string lsdyna;                        // LS-DYNA keyword file (optional)
};

struct TransformReport {
  engine::Kinematics kinematics;
  engine::TestSummary summary;
  std::vector<std::string> warnings;
};

// Reads, solves and writes every requested output; nothing is written unless
// everything succeeded (outputs are renamed into place at the end). Throws
// InputError with one sentence naming the file, channel or row at fault.
TransformReport RunTransform(const TransformOptions& options);

}  // namespace napkin::app
