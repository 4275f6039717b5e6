#include "postproc/analyses/animate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/output_path.hpp"
#include "postproc/analysis.hpp"
#include "postproc/flexible_body.hpp"
#include "postproc/output.hpp"
#include "postproc/surface_motion.hpp"
#include "postproc/surface_radiation.hpp"
#include "postproc/xdmf.hpp"

namespace nvh::postproc {

std::filesystem::path animation_data_path(const std::filesystem::path& xdmf) {
  std::filesystem::path h5 = xdmf;
  return h5.replace_extension(".h5");
}

namespace {

/// Row `sample` of the signals (one per column), as a vector.
Eigen::VectorXd read_row(const std::vector<SignalSource>& columns, std::int64_t sample) {
  Eigen::VectorXd row(static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c)
    columns[c].read(sample, std::span<double>(&row[static_cast<Eigen::Index>(c)], 1));
  return row;
}

/// The triangles as a (t, 3) int64 dataset (XDMF's Triangle topology), each index checked against the nodes.
void write_triangles(h5::Group& g, const std::string& name, const std::vector<std::array<int, 3>>& triangles,
                     std::int64_t nodes, const std::string& source) {
  std::vector<std::int64_t> flat;
  flat.reserve(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (const int i : triangles[t]) {
      if (i < 0 || i >= nodes)
        throw Error(source + ":/surface/triangles: triangle " + std::to_string(t) + " has node index " +
                    std::to_string(i) + "; expected 0 to " + std::to_string(nodes - 1));
      flat.push_back(i);
    }
  const hsize_t dims[2] = {static_cast<hsize_t>(triangles.size()), 3};
  const h5::Handle space(H5Screate_simple(2, dims, nullptr));
  h5::Handle set(
      H5Dcreate2(g.id(), name.c_str(), H5T_STD_I64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  // The close writes what HDF5 still buffers (a full disk fails there): checked, not left to the Handle.
  if (!set.valid() || H5Dwrite(set.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, flat.data()) < 0 ||
      H5Dclose(set.release()) < 0)
    throw Error("cannot write the dataset " + g.path() + "/" + name);
}

/// First and last sample of the window: --from/--to in s on /time, or --from-deg/--to-deg on
/// /crank_angle_deg (each value within 1e-6 of a sample's includes it).
std::pair<std::int64_t, std::int64_t> window_samples(const Eigen::VectorXd& axis, const std::string& where,
                                                     const char* unit, std::optional<double> from,
                                                     std::optional<double> to, const char* from_option,
                                                     const char* to_option) {
  const auto n = static_cast<std::int64_t>(axis.size());
  const double first = axis[0], last = axis[n - 1];
  const double tol = 1e-6 * (n > 1 ? (last - first) / static_cast<double>(n - 1) : 1.0);
  for (std::size_t i = 1; i < static_cast<std::size_t>(n); ++i)
    if (!(axis[static_cast<Eigen::Index>(i)] > axis[static_cast<Eigen::Index>(i - 1)]))
      throw Error(where + ": sample " + std::to_string(i) + " is not after sample " + std::to_string(i - 1) +
                  "; expected increasing values");
  auto outside = [&](const char* option, double v) {
    std::ostringstream msg;
    msg << option << " " << v << " " << unit << " is outside the run: " << where << " spans " << first
        << " to " << last << " " << unit;
    return Error(msg.str());
  };
  const double lo = from.value_or(first), hi = to.value_or(last);
  if (from && (lo < first - tol || lo > last + tol)) throw outside(from_option, lo);
  if (to && (hi < first - tol || hi > last + tol)) throw outside(to_option, hi);
  if (hi < lo) {
    std::ostringstream msg;
    msg << from_option << " " << lo << " " << unit << " is after " << to_option << " " << hi << " " << unit
        << "; expected " << from_option << " <= " << to_option;
    throw Error(msg.str());
  }
  const auto begin = std::lower_bound(axis.data(), axis.data() + n, lo - tol) - axis.data();
  const auto end = std::upper_bound(axis.data(), axis.data() + n, hi + tol) - axis.data() - 1;
  if (end < begin) {
    std::ostringstream msg;
    msg << from_option << " " << lo << " to " << to_option << " " << hi << " " << unit
        << " holds no sample of " << where << "; expected a window around at least one sample";
    throw Error(msg.str());
  }
  return {begin, end};
}

std::string frame_group(std::size_t f) {
  char name[32];
  std::snprintf(name, sizeof name, "frames/%06zu", f);
  return name;
}

}  // namespace

void run_animate(const AnimateCommand& command, const Logger& log, int argc, const char* const* argv) {
  const auto started = std::chrono::steady_clock::now();
  const std::string xdmf_ext = command.output.extension().string();
  if (xdmf_ext != ".xdmf" && xdmf_ext != ".xmf")
    throw Error("animate: -o " + command.output.string() +
                ": expected an .xdmf (or .xmf) file name; the data go to the .h5 file beside it");
  if (!std::isfinite(command.scale) || command.scale == 0.0)
    throw Error("animate: --scale must be a finite, non-zero number");
  if (command.max_frames < 1) throw Error("animate: --frames must be at least 1");
  if ((command.from_s || command.to_s) && (command.from_deg || command.to_deg))
    throw Error("animate: --from/--to (s) and --from-deg/--to-deg (crank angle) exclude each other");
  const std::filesystem::path h5_path = animation_data_path(command.output);
  const std::string results = command.results.string();

  const std::vector<SignalSource> eta = open_body_columns(command.results, command.body, "modal_coordinates");
  const std::vector<SignalSource> eta_dot =
      open_body_columns(command.results, command.body, "modal_velocities");
  const auto modes = static_cast<Eigen::Index>(eta.size());
  if (eta_dot.size() != eta.size() || eta_dot.front().size() != eta.front().size())
    throw Error(results + ":/bodies/" + command.body + ": modal_velocities (" +
                std::to_string(eta_dot.front().size()) + " x " + std::to_string(eta_dot.size()) +
                ") and modal_coordinates (" + std::to_string(eta.front().size()) + " x " +
                std::to_string(eta.size()) + "); expected the same shape");
  const SuperelementFile se = read_body_surface(command.superelement, command.results, command.body, modes);
  const SurfaceExport& surface = *se.surface;
  const auto nodes = static_cast<std::int64_t>(surface.labels.size());
  if (surface.triangles.empty())
    throw Error(command.superelement.string() +
                ": no /surface/triangles; expected the exported surface's triangles (the mesh to draw)");
  std::vector<SignalSource> frame;  // r_O (3), p (4), v_O (3), omega (3): global axes
  if (command.include_rigid)
    frame = open_frame_columns(
        command.results, command.body,
        {{"position", 3}, {"euler_parameters", 4}, {"velocity", 3}, {"angular_velocity", 3}}, eta.front());

  // The time axis and the crank angle, read whole (8 bytes a sample), and the window's samples.
  Eigen::VectorXd time, angle;
  {
    h5::File file = h5::File::open_read(command.results);
    time = file.root().read_vector("time", static_cast<hsize_t>(eta.front().size()));
    if (file.root().exists("crank_angle_deg"))
      angle = file.root().read_vector("crank_angle_deg", static_cast<hsize_t>(time.size()));
  }
  std::pair<std::int64_t, std::int64_t> window;
  if (command.from_deg || command.to_deg) {
    if (angle.size() == 0)
      throw Error(
          "animate: --from-deg/--to-deg: " + results +
          " has no /crank_angle_deg; expected solve's results of a scene with a [clock] (or use --from "
          "and --to in s)");
    window = window_samples(angle, results + ":/crank_angle_deg", "deg", command.from_deg, command.to_deg,
                            "--from-deg", "--to-deg");
  } else {
    window = window_samples(time, results + ":/time", "s", command.from_s, command.to_s, "--from", "--to");
  }
  const std::vector<std::int64_t> samples = select_frames(window.first, window.second, command.max_frames);
  const std::int64_t stride = samples.size() > 1 ? samples[1] - samples[0] : 1;

  check_outputs_are_not_inputs({command.output, h5_path}, {command.results, command.superelement});
  check_output_writable(command.output);
  check_output_writable(h5_path);
  std::future<Provenance> provenance = start_provenance({command.results, command.superelement}, argc, argv);

  CommonOptions common;
  common.output = h5_path;
  Output out = create_output(common, provenance, "animate");
  h5::Group& root = out.root;
  const std::string elastic_text =
      "elastic displacement u = Phi eta in the body's floating frame (body axes); rigid-body motion excluded";
  const std::string rigid_text =
      "displacement d = r_O + A (x + Phi eta) - x in global axes (the frame's rigid-body motion and the "
      "elastic displacement): x + d is the node's position in the scene";
  root.set_attribute("results", results);
  root.set_attribute("superelement", command.superelement.string());
  root.set_attribute("body", command.body);
  root.set_attribute("xdmf", command.output.filename().string());
  root.set_attribute("modes", static_cast<std::int64_t>(modes));
  root.set_attribute("surface_nodes", nodes);
  root.set_attribute("triangles", static_cast<std::int64_t>(surface.triangles.size()));
  root.set_attribute("frames", static_cast<std::int64_t>(samples.size()));
  root.set_attribute("stride_samples", stride);
  root.set_attribute("window_start_s", time[samples.front()]);
  root.set_attribute("window_end_s", time[samples.back()]);
  root.set_attribute("scale", command.scale);
  root.set_attribute("geometry", command.displaced_geometry
                                     ? "per frame: x + scale d (frames/NNNNNN/position)"
                                     : "undeformed surface x (surface/position) for every frame");
  root.set_attribute("displacement_frame", command.include_rigid ? rigid_text : elastic_text);
  root.set_attribute("velocity_frame",
                     command.include_rigid
                         ? "absolute normal velocity: n . Phi eta' plus the frame's rigid-body "
                           "motion n . (v_O + omega x r)"
                         : "normal velocity relative to the body's floating frame (elastic "
                           "part, v_n = n . Phi eta'); rigid-body motion excluded");

  h5::Group s = root.create_group("surface");
  s.write("position", surface.position);
  s.set_attribute("units", "m", "position");
  s.set_attribute("description", "undeformed surface nodes, component axes", "position");
  write_triangles(s, "triangles", surface.triangles, nodes, command.superelement.string());
  s.set_attribute("description", "(triangles, 3): 0-based rows of surface/position, oriented outward",
                  "triangles");
  s.write("node_label", std::span<const std::int64_t>(surface.labels));
  s.write("normal", surface.normal);
  s.set_attribute("units", "1", "normal");
  s.write("area", surface.area);
  s.set_attribute("units", "m^2", "area");

  Eigen::VectorXd frame_time(static_cast<Eigen::Index>(samples.size()));
  Eigen::VectorXd frame_angle(angle.size() > 0 ? frame_time.size() : 0);
  std::vector<std::int64_t> frame_sample(samples.begin(), samples.end());
  for (std::size_t f = 0; f < samples.size(); ++f) {
    frame_time[static_cast<Eigen::Index>(f)] = time[samples[f]];
    if (angle.size() > 0) frame_angle[static_cast<Eigen::Index>(f)] = angle[samples[f]];
  }
  h5::Group fr = root.create_group("frames");
  fr.write("time", frame_time);
  fr.set_attribute("units", "s", "time");
  fr.write("sample", std::span<const std::int64_t>(frame_sample));
  fr.set_attribute("description", "0-based row of each frame in the results' datasets", "sample");
  if (angle.size() > 0) {
    fr.write("crank_angle_deg", frame_angle);
    fr.set_attribute("units", "deg", "crank_angle_deg");
  }

  const Eigen::MatrixXd psi = surface_normal_shapes(surface, static_cast<int>(modes));
  const Eigen::MatrixXd psi_rigid =
      command.include_rigid ? rigid_normal_shapes(surface.position, surface.normal) : Eigen::MatrixXd();
  const std::string h5_name = h5_path.filename().string();
  XdmfSurfaceSeries series;
  series.h5_file = h5_name;
  series.name = command.body;
  series.nodes = nodes;
  series.triangles = static_cast<std::int64_t>(surface.triangles.size());
  series.topology = "/surface/triangles";
  {
    std::ostringstream scale;
    scale.precision(17);
    scale << command.scale;
    series.information = {{"body", command.body},
                          {"scale", scale.str()},
                          {"units", "SI: time s, geometry and displacement m, normal_velocity m/s"},
                          {"displacement", command.include_rigid ? rigid_text : elastic_text},
                          {"geometry", command.displaced_geometry ? "x + scale d per frame"
                                                                  : "undeformed; Warp By Vector "
                                                                    "with displacement x scale"}};
  }
  for (std::size_t f = 0; f < samples.size(); ++f) {
    const Eigen::VectorXd q = read_row(eta, samples[f]), qd = read_row(eta_dot, samples[f]);
    const Eigen::MatrixXd u = elastic_displacement(surface, q);
    Eigen::VectorXd vn = psi * qd;
    Eigen::MatrixXd d = u, position;
    Eigen::Vector3d origin;
    Eigen::Vector4d p;
    if (command.include_rigid) {
      const Eigen::VectorXd g = read_row(frame, samples[f]);
      origin = g.segment<3>(0);
      p = g.segment<4>(3);
      d = rigid_motion_displacement(surface.position, u, origin, p);
      vn += psi_rigid * body_frame_velocity(g.segment<3>(7), g.segment<3>(10), p);
    }
    const std::string group = frame_group(f);
    h5::Group fg = root.create_group(group);
    fg.set_attribute("time_s", frame_time[static_cast<Eigen::Index>(f)]);
    fg.set_attribute("sample", samples[f]);
    fg.write("displacement", d);
    fg.set_attribute("units", "m", "displacement");
    fg.write("normal_velocity", vn);
    fg.set_attribute("units", "m/s", "normal_velocity");
    XdmfFrame xf;
    xf.time = frame_time[static_cast<Eigen::Index>(f)];
    xf.geometry = "/surface/position";
    if (command.displaced_geometry) {
      position = command.include_rigid
                     ? Eigen::MatrixXd(surface.position + rigid_motion_displacement(
                                                              surface.position, command.scale * u, origin, p))
                     : Eigen::MatrixXd(surface.position + command.scale * u);
      fg.write("position", position);
      fg.set_attribute("units", "m", "position");
      xf.geometry = "/" + group + "/position";
    }
    xf.fields = {{"displacement", "/" + group + "/displacement", 3},
                 {"normal_velocity", "/" + group + "/normal_velocity", 1}};
    series.frames.push_back(std::move(xf));
  }

  std::vector<TextOutput> xdmf;
  xdmf.emplace_back(command.output);
  xdmf.front().stream() << xdmf_text(series);
  xdmf.front().close();
  commit_outputs(out, xdmf);

  std::ostringstream msg;
  msg.precision(6);
  msg << command.body << ": " << samples.size() << " frames (every " << stride << " samples, "
      << time[samples.front()] << " to " << time[samples.back()] << " s) of " << nodes << " surface nodes, "
      << surface.triangles.size() << " triangles, " << modes << " modes -> " << command.output.string()
      << ", " << h5_name << " ("
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() << " s)";
  log.info(msg.str());
}

namespace {

class AnimateAnalysis final : public Analysis {
 public:
  void add_options(CLI::App& a, CliShared&) override {
    a.add_option("RESULTS", command_.results, "solve's results file (HDF5)")->required();
    a.add_option("--superelement", command_.superelement,
                 "the body's superelement file, with its exported /surface")
        ->required();
    a.add_option("--body", command_.body, "the flexible body in the results (/bodies/<name>)")->required();
    a.add_option("-o,--output", command_.output,
                 "XDMF file to write (OUT.xdmf; the data go to OUT.h5 beside it; temporaries renamed when "
                 "complete)")
        ->required();
    a.add_option_function<double>(
        "--from", [this](double t) { command_.from_s = t; },
        "first frame at this time, s (default: the run's start)");
    a.add_option_function<double>(
        "--to", [this](double t) { command_.to_s = t; },
        "last frame at this time, s (default: the run's end)");
    a.add_option_function<double>(
        "--from-deg", [this](double a) { command_.from_deg = a; },
        "instead of --from: first frame at this crank angle, deg of /crank_angle_deg");
    a.add_option_function<double>(
        "--to-deg", [this](double a) { command_.to_deg = a; },
        "instead of --to: last frame at this crank angle, deg of /crank_angle_deg");
    a.add_option("--frames", command_.max_frames,
                 "at most this many frames, evenly spaced samples of the window (default 200)")
        ->check(CLI::PositiveNumber);
    a.add_flag("--include-rigid", command_.include_rigid,
               "add the frame's rigid-body motion: displacement in global axes, absolute normal velocity");
    a.add_option(
        "--scale", command_.scale,
        "displacement scale factor for ParaView's Warp By Vector, recorded in the files (default 1)");
    a.add_flag("--displaced-geometry", command_.displaced_geometry,
               "also write the displaced surface x + scale d per frame and use it as the geometry");
  }

  void run(const Logger& log, int argc, const char* const* argv) override {
    run_animate(command_, log, argc, argv);
  }

  std::filesystem::path output() const override { return animation_data_path(command_.output); }

 private:
  AnimateCommand command_;
};

}  // namespace

std::unique_ptr<Analysis> make_animate_analysis() {
  return std::make_unique<AnimateAnalysis>();
}

}  // namespace nvh::postproc
