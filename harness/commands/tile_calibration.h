// `pcbench calibrate` on scenes: prints and writes the calibration of the block pyramid that
// harness/verify/scene_calibration.h computes.
#pragma once

#include <iosfwd>
#include <nlohmann/json_fwd.hpp>

#include "harness/session/session.h"
#include "harness/verify/scene_calibration.h"

namespace pcbench {

// The report's optional top-level `tile_calibration` ($defs/tileCalibration in
// results/report.schema.json).
nlohmann::ordered_json tile_calibration_json(const TileCalibrationResult& result);

// The size table (each row, then its scales), then the power curves (per pair and rule, one
// line per scale and k).
void print_tile_calibration(const TileCalibrationResult& result, std::ostream& out);

// `pcbench calibrate` on scenes: runs calibrate_tiles(), prints it, writes a report whose
// `tile_calibration` holds it. Exit 0 when every size row passes, 1 when one does not.
int run_tile_calibration(const TileCalibrationOptions& options, const SessionOptions& session,
                         std::ostream& out, std::ostream& err);

}  // namespace pcbench
