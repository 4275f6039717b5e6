#pragma once
// A scene: the model and how to run it, read from a TOML scene file (docs/scene-format.md).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "solve/integrator.hpp"
#include "solve/model.hpp"
#include "solve/steady_state_settings.hpp"

namespace nvh::solve {

struct OutputSettings {
  double sample_rate_hz = 10000;
  std::vector<std::string> markers;  // "body.marker"; empty = every marker of every moving body
  bool bodies = true, forces = true, joints = true;
  int chunk_samples = 2048;  // samples per flush (and per checkpoint)
  int compression = 1;       // gzip level of the time histories, 0 (none) .. 9 (h5::Group::kTimeHistory's 1)
};

struct Scene {
  std::string name;
  Model model;
  IntegratorSettings integrator;
  OutputSettings output;
  double start_time = 0;
  double end_time = 0;                    // s: the end, or a bound when the run ends by crank angle
  double end_angle_deg = 0;               // > 0: end when the clock's crank angle has advanced this far
  std::vector<std::string> marker_names;  // "body.marker" for every MarkerRef in output order
  std::vector<MarkerRef> output_markers;
  std::vector<std::filesystem::path> input_files;   // the scene and every file it reads (provenance)
  std::optional<SteadyStateSettings> steady_state;  // [steady_state]: run cycles until periodic
  std::vector<std::string>
      warnings;  // choices that are allowed but likely wrong: solve logs them before a run
};

/// Read and check a scene file; every error names the file, line and key. Relative paths inside the scene
/// (tables, superelements) are relative to the scene file's folder.
Scene read_scene(const std::filesystem::path& path);
/// The same from text (tests); `base` is the folder for relative paths.
Scene parse_scene(const std::string& text, const std::string& name, const std::filesystem::path& base);

}  // namespace nvh::solve
