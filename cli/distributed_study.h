// `hedra shadows --sun-hours ... --workers N | --scheduler ADDRESS`: the sun study on a Dask
// cluster, run by the Python module (python/hedra/distributed.py, docs/distributed.md).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "hedra/visibility/shadows.h"

namespace hedra::cli {

/// Where the study runs: `workers` > 0 starts a local cluster of that many processes;
/// otherwise `scheduler` is the address of a running Dask scheduler.
struct DaskTarget {
  int workers = 0;
  std::string scheduler;
};

/// Runs `/usr/bin/python3 -m hedra.distributed shadows` (HEDRA_PYTHON overrides the
/// interpreter) with the module found next to this executable (build/python, or the install
/// prefix's site-packages) ahead of PYTHONPATH, and returns the `sun_study` part of the JSON
/// report: the single-process study's, bit for bit (the module combines the slices in step
/// order). The times are passed as the kernel prints them, the step with 17 digits.
/// \throw InvalidInput (its message without the scene file's name, which the caller adds) with
///   the module's one-line message when Python, the module or Dask is
///   missing, the scheduler cannot be reached, or the study fails; IoError for temporary files.
nlohmann::json distributed_sun_study(const std::string& scene_file,
                                     const SunStudyOptions& options, const DaskTarget& target);

/// The summary line of a sun study (as `hedra shadows` prints it) from its JSON.
std::string sun_study_summary(const nlohmann::json& study);

}  // namespace hedra::cli
