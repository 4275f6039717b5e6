#include "postproc/analyses/erp.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "common/hdf5.hpp"
#include "common/superelement.hpp"
#include "postproc/analysis.hpp"
#include "postproc/cli_options.hpp"
#include "postproc/csv.hpp"
#include "postproc/flexible_body.hpp"
#include "postproc/levels.hpp"
#include "postproc/octave.hpp"
#include "postproc/output.hpp"
#include "postproc/signal.hpp"
#include "postproc/windowing.hpp"

namespace nvh::postproc {
namespace {

int segment_length(const ErpCommand& command, double fs, std::int64_t samples, const std::string& name) {
  if (command.segment_length > 0 || command.resolution_hz > 0.0) {
    SpectrumOptions o;
    o.segment_length = command.segment_length;
    o.resolution_hz = command.resolution_hz;
    return segment_length_for(o, fs, samples, name);
  }
  if (samples < 16)
    throw Error("erp: " + name + " has " + std::to_string(samples) + " samples; expected at least 16");
  int n = 16;
  while (2 * static_cast<std::int64_t>(n) <= samples && n < (1 << 26)) n *= 2;
  return n;
}

std::vector<Band> bands_for(const ErpCommand& command, double fs, double df) {
  const double half_band = std::pow(10.0, 0.3 / (2.0 * command.fraction));
  double fmax = command.fmax_hz;
  if (fmax <= 0.0) fmax = std::min(10000.0, 0.999 * fs / 2.0 / half_band / std::sqrt(half_band));
  double fmin = command.fmin_hz;
  if (fmin <= 0.0) fmin = std::max(20.0, 2.0 * df / (half_band - 1.0 / half_band));
  std::vector<Band> bands = fractional_octave_bands(command.fraction, fmin, fmax);
  if (command.fmin_hz <= 0.0)  // the automatic lower limit: only bands at least 2 bins wide
    std::erase_if(bands, [df](const Band& b) { return b.upper_hz - b.lower_hz < 2.0 * df; });
  if (bands.empty()) {
    std::ostringstream msg;
    msg << "erp: no 1/" << command.fraction << "-octave band between " << fmin << " and " << fmax
        << " Hz at a resolution of " << df << " Hz; expected a longer window or a finer --resolution";
    throw Error(msg.str());
  }
  for (const Band& b : bands)
    if (b.upper_hz >= fs / 2.0) {
      std::ostringstream msg;
      msg << "erp: band " << b.nominal_hz << " Hz reaches the Nyquist frequency " << fs / 2.0
          << " Hz; expected a lower --fmax";
      throw Error(msg.str());
    }
  return bands;
}

/// Band sums of PSD columns: (bands x columns), each the integral of the PSD over the band.
Eigen::MatrixXd band_sums(const Eigen::VectorXd& f, double df, const Eigen::MatrixXd& psd,
                          const std::vector<Band>& bands) {
  Spectrum s;
  s.type = SpectrumType::kPsd;
  s.frequency_hz = f;
  s.resolution_hz = df;
  Eigen::MatrixXd out(static_cast<Eigen::Index>(bands.size()), psd.cols());
  for (Eigen::Index c = 0; c < psd.cols(); ++c) {
    s.values = psd.col(c);
    const std::vector<double> ms = band_mean_square_from_psd(s, bands);
    for (std::size_t b = 0; b < ms.size(); ++b) out(static_cast<Eigen::Index>(b), c) = ms[b];
  }
  return out;
}

Eigen::VectorXd levels(const Eigen::VectorXd& values, const LevelReference& ref, bool mean_square) {
  Eigen::VectorXd l(values.size());
  for (Eigen::Index i = 0; i < values.size(); ++i)
    l[i] = level_db(mean_square ? std::sqrt(values[i]) : values[i], ref);
  return l;
}

void write_bands(h5::Group& g, const std::vector<Band>& bands) {
  Eigen::VectorXd c(static_cast<Eigen::Index>(bands.size())), lo(c.size()), hi(c.size()), nom(c.size());
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const auto i = static_cast<Eigen::Index>(b);
    c[i] = bands[b].center_hz;
    lo[i] = bands[b].lower_hz;
    hi[i] = bands[b].upper_hz;
    nom[i] = bands[b].nominal_hz;
  }
  for (const auto& [name, v] :
       {std::pair{"center_hz", &c}, {"lower_hz", &lo}, {"upper_hz", &hi}, {"nominal_hz", &nom}}) {
    g.write(name, *v);
    g.set_attribute("units", "Hz", name);
  }
}

}  // namespace

void run_erp(const ErpCommand& command, const Logger& log, int argc, const char* const* argv) {
  const CommonOptions& common = command.common;
  if (!(command.density_kg_m3 > 0.0) || !(command.sound_speed_m_s > 0.0))
    throw Error("erp: --rho and --sound-speed must be positive");
  std::vector<SignalSource> modal = open_body_columns(command.results, command.body, "modal_velocities");
  const auto modes = static_cast<Eigen::Index>(modal.size());
  const SuperelementFile se = read_body_surface(command.superelement, command.results, command.body, modes);
  const SurfaceExport& surface = *se.surface;
  const auto nodes = static_cast<Eigen::Index>(surface.labels.size());

  // Regions before any work: each must hold nodes.
  std::vector<std::vector<Eigen::Index>> region_nodes;
  for (const SurfaceRegion& r : command.regions) {
    region_nodes.push_back(nodes_in_region(surface.position, r));
    if (region_nodes.back().empty()) {
      std::ostringstream msg;
      msg << "--region " << r.name << ": no surface node of " << command.superelement.string()
          << " inside the box [" << r.lower.transpose() << "] - [" << r.upper.transpose()
          << "] m (component axes); expected a box around part of the surface";
      throw Error(msg.str());
    }
  }
  std::vector<std::string> csv_names;
  if (common.csv_dir) csv_names = {"erp_" + command.body + ".csv", "erp_spectrum_" + command.body + ".csv"};
  check_outputs_are_not_inputs(
      [&] {
        std::vector<std::filesystem::path> o{common.output};
        for (const std::string& n : csv_names) o.push_back(*common.csv_dir / n);
        return o;
      }(),
      {command.results, command.superelement});
  check_output_writable(common.output);
  if (common.csv_dir) check_output_directory(*common.csv_dir);

  // With --include-rigid: the frame's velocity, angular velocity (global axes) and Euler parameters, sampled
  // with the modal velocities (solve writes them for every body).
  std::vector<SignalSource> frame;
  if (command.include_rigid)
    frame = open_frame_columns(command.results, command.body,
                               {{"velocity", 3}, {"angular_velocity", 3}, {"euler_parameters", 4}},
                               modal.front());
  for (SignalSource& s : modal) apply_window(s, common.window, nullptr, 0.0, common.block, log);
  for (SignalSource& s : frame) apply_window(s, common.window, nullptr, 0.0, common.block, log);
  std::future<Provenance> provenance = start_provenance({command.results, command.superelement}, argc, argv);
  const SignalInfo& info = modal.front().info();
  const double fs = info.sample_rate_hz;
  int n = 0;
  try {
    n = segment_length(command, fs, info.size,
                       "'" + command.results.string() + ":/bodies/" + command.body + "/modal_velocities'");
  } catch (const Error& e) {
    rethrow_in_window(e, common.window, modal.front());
  }

  // Surface nodes, then observation points with normals: one Psi (eq. 1).
  const Eigen::MatrixXd psi_surface = surface_normal_shapes(surface, static_cast<int>(modes));
  const Eigen::MatrixXd psi_observe = observer_normal_shapes(se.observers, static_cast<int>(modes));
  const Eigen::Index rigid = command.include_rigid ? 6 : 0;  // (v_O, omega) in body axes, eq. (1a)
  Eigen::MatrixXd psi(nodes + psi_observe.rows(), modes + rigid);
  psi.topLeftCorner(nodes, modes) = psi_surface;
  psi.bottomLeftCorner(psi_observe.rows(), modes) = psi_observe;
  if (rigid) {
    psi.topRightCorner(nodes, 6) = rigid_normal_shapes(surface.position, surface.normal);
    if (psi_observe.rows() > 0)
      psi.bottomRightCorner(psi_observe.rows(), 6) =
          rigid_normal_shapes(se.observers.position, se.observers.normals);
  }
  NormalVelocityWelch welch(fs, n, command.window, command.overlap, psi);
  {
    std::vector<double> column;
    Eigen::MatrixXd block;
    for (std::int64_t offset = 0; offset < info.size; offset += common.block) {
      const std::int64_t count = std::min(common.block, info.size - offset);
      column.resize(static_cast<std::size_t>(count));
      block.resize(count, modes + rigid);
      for (Eigen::Index j = 0; j < modes; ++j) {
        modal[static_cast<std::size_t>(j)].read(offset, column);
        block.col(j) = Eigen::Map<const Eigen::VectorXd>(column.data(), count);
      }
      if (rigid) {
        Eigen::MatrixXd global(count, 10);  // v (3), omega (3), p (4)
        for (std::size_t c = 0; c < frame.size(); ++c) {
          frame[c].read(offset, column);
          global.col(static_cast<Eigen::Index>(c)) = Eigen::Map<const Eigen::VectorXd>(column.data(), count);
        }
        for (Eigen::Index i = 0; i < count; ++i)
          block.block<1, 6>(i, modes) =
              body_frame_velocity(global.block<1, 3>(i, 0).transpose(), global.block<1, 3>(i, 3).transpose(),
                                  global.block<1, 4>(i, 6).transpose())
                  .transpose();
      }
      welch.push(block);
    }
  }
  const Eigen::MatrixXd psd = welch.psd();
  const Eigen::VectorXd f = welch.frequency_hz();
  const double df = welch.resolution_hz();
  const std::vector<Band> bands = bands_for(command, fs, df);
  const double rho_c = command.density_kg_m3 * command.sound_speed_m_s;

  std::vector<Eigen::Index> all(static_cast<std::size_t>(nodes));
  for (Eigen::Index k = 0; k < nodes; ++k) all[static_cast<std::size_t>(k)] = k;
  // Spectral densities: ERP (eq. 3) and area-mean square velocity, whole surface then each region.
  Eigen::MatrixXd densities(f.size(), 2 * (1 + static_cast<Eigen::Index>(command.regions.size())));
  densities.col(0) = erp_density(psd, surface.area, rho_c, all);
  densities.col(1) = area_mean_psd(psd, surface.area, all);
  for (std::size_t r = 0; r < command.regions.size(); ++r) {
    densities.col(2 + 2 * static_cast<Eigen::Index>(r)) =
        erp_density(psd, surface.area, rho_c, region_nodes[r]);
    densities.col(3 + 2 * static_cast<Eigen::Index>(r)) = area_mean_psd(psd, surface.area, region_nodes[r]);
  }
  const Eigen::MatrixXd band = band_sums(f, df, densities, bands);
  const Eigen::MatrixXd node_band = band_sums(f, df, psd, bands);  // bands x points (mean squares)

  const LevelReference power_ref = level_reference("power", "W", common.velocity_reference);
  const LevelReference velocity_ref = level_reference("velocity", "m/s", common.velocity_reference);
  const double total_erp = densities.col(0).sum() * df;

  Output out = create_output(common, provenance, "erp");
  h5::Group g = out.root.create_group("erp/" + sanitize_name(command.body));
  g.set_attribute("results", command.results.string());
  g.set_attribute("superelement", command.superelement.string());
  g.set_attribute("body", command.body);
  g.set_attribute("signal", info.address.substr(0, info.address.rfind('[')));
  g.set_attribute("sample_rate_hz", fs);
  g.set_attribute("samples", static_cast<std::int64_t>(info.size));
  g.set_attribute("duration_s", static_cast<double>(info.size) / fs);
  g.set_attribute("window_start_s", info.start_time_s);
  g.set_attribute("window_end_s", window_end_s(info));
  g.set_attribute("modes", static_cast<std::int64_t>(modes));
  g.set_attribute("surface_nodes", static_cast<std::int64_t>(nodes));
  g.set_attribute("surface_area_m2", surface.area.sum());
  g.set_attribute(
      "velocity_frame",
      command.include_rigid
          ? "absolute normal velocity: elastic part n . Phi eta' plus the frame's rigid-body motion "
            "n . (v_O + omega x r)"
          : "normal velocity relative to the body's floating frame (elastic part, v_n = n . Phi "
            "eta'); rigid-body motion of the frame excluded");
  g.set_attribute("density_kg_m3", command.density_kg_m3);
  g.set_attribute("sound_speed_m_s", command.sound_speed_m_s);
  g.set_attribute("rho_c_kg_m2_s", rho_c);
  g.set_attribute("window", to_string(command.window));
  g.set_attribute("segment_length", static_cast<std::int64_t>(welch.segment_length()));
  g.set_attribute("overlap", welch.overlap());
  g.set_attribute("averages", static_cast<std::int64_t>(welch.averages()));
  g.set_attribute("resolution_hz", df);
  g.set_attribute("enbw_hz", welch.enbw_hz());
  g.set_attribute("fraction", static_cast<std::int64_t>(command.fraction));

  g.write("frequency_hz", f);
  g.set_attribute("units", "Hz", "frequency_hz");
  g.write("erp_density", densities.col(0));
  g.set_attribute("units", "W/Hz", "erp_density");
  g.set_attribute("description",
                  "rho c sum_k A_k PSD_k(f): ERP per unit frequency (one-sided, energy-correct)",
                  "erp_density");
  g.write("erp_bin_w", Eigen::VectorXd(densities.col(0) * welch.enbw_hz()));
  g.set_attribute("units", "W", "erp_bin_w");
  g.set_attribute(
      "description",
      "erp_density x enbw_hz: a harmonic surface velocity reads its ERP 1/2 rho c sum A |v_hat|^2 at "
      "its bin (amplitude-correct)",
      "erp_bin_w");
  g.write("velocity_psd", densities.col(1));
  g.set_attribute("units", "(m/s)^2/Hz", "velocity_psd");
  g.set_attribute("description", "area-weighted mean over the surface of the normal-velocity PSD",
                  "velocity_psd");
  write_bands(g, bands);
  const Eigen::VectorXd erp_band = band.col(0), erp_level = levels(erp_band, power_ref, false);
  const Eigen::VectorXd velocity_level = levels(band.col(1), velocity_ref, true);
  g.write("erp_band_w", erp_band);
  g.set_attribute("units", "W", "erp_band_w");
  g.write("erp_level_db", erp_level);
  write_reference(g, "erp_level_db", power_ref);
  g.write("overall_erp_w", total_erp);
  g.set_attribute("units", "W", "overall_erp_w");
  g.set_attribute("description", "ERP over all bins (DC to Nyquist)", "overall_erp_w");
  g.write("overall_erp_level_db", level_db(total_erp, power_ref));
  write_reference(g, "overall_erp_level_db", power_ref);
  g.write("velocity_level_db", velocity_level);
  write_reference(g, "velocity_level_db", velocity_ref);
  g.set_attribute("description", "band level of the area-weighted mean square normal velocity",
                  "velocity_level_db");
  g.write("node_label", std::span<const std::int64_t>(surface.labels));
  g.write("node_area", surface.area);
  g.set_attribute("units", "m^2", "node_area");
  Eigen::MatrixXd node_level(nodes, static_cast<Eigen::Index>(bands.size()));
  for (Eigen::Index k = 0; k < nodes; ++k)
    node_level.row(k) = levels(node_band.col(k), velocity_ref, true).transpose();
  g.write("node_velocity_level_db", node_level);
  write_reference(g, "node_velocity_level_db", velocity_ref);
  if (command.node_spectra) {
    g.write("node_velocity_psd", Eigen::MatrixXd(psd.leftCols(nodes).transpose()));
    g.set_attribute("units", "(m/s)^2/Hz", "node_velocity_psd");
    g.set_attribute("description", "normal-velocity PSD per (surface node, frequency)", "node_velocity_psd");
  }
  for (std::size_t r = 0; r < command.regions.size(); ++r) {
    const SurfaceRegion& region = command.regions[r];
    const auto c = static_cast<Eigen::Index>(r);
    h5::Group rg = g.create_group("regions/" + sanitize_name(region.name));
    rg.set_attribute("box_m", std::vector<double>{region.lower.x(), region.lower.y(), region.lower.z(),
                                                  region.upper.x(), region.upper.y(), region.upper.z()});
    double area = 0.0;
    for (const Eigen::Index k : region_nodes[r]) area += surface.area[k];
    rg.write("node_count", static_cast<std::int64_t>(region_nodes[r].size()));
    rg.write("area_m2", area);
    rg.set_attribute("units", "m^2", "area_m2");
    const Eigen::VectorXd rb = band.col(2 + 2 * c);
    rg.write("erp_band_w", rb);
    rg.set_attribute("units", "W", "erp_band_w");
    rg.write("erp_level_db", levels(rb, power_ref, false));
    write_reference(rg, "erp_level_db", power_ref);
    Eigen::VectorXd share(rb.size());
    for (Eigen::Index b = 0; b < rb.size(); ++b) share[b] = erp_band[b] > 0.0 ? rb[b] / erp_band[b] : 0.0;
    rg.write("erp_share", share);
    rg.set_attribute("units", "1", "erp_share");
    rg.set_attribute("description", "the region's part of the surface's ERP per band", "erp_share");
    rg.write("velocity_level_db", levels(band.col(3 + 2 * c), velocity_ref, true));
    write_reference(rg, "velocity_level_db", velocity_ref);
  }
  for (Eigen::Index p = 0; p < psi_observe.rows(); ++p) {
    const std::string& name = se.observers.names[static_cast<std::size_t>(p)];
    h5::Group og = g.create_group("observe/" + sanitize_name(name));
    og.set_attribute("position_m",
                     std::vector<double>{se.observers.position(p, 0), se.observers.position(p, 1),
                                         se.observers.position(p, 2)});
    og.write("velocity_psd", Eigen::VectorXd(psd.col(nodes + p)));
    og.set_attribute("units", "(m/s)^2/Hz", "velocity_psd");
    og.write("velocity_level_db", levels(node_band.col(nodes + p), velocity_ref, true));
    write_reference(og, "velocity_level_db", velocity_ref);
  }

  std::ostringstream msg;
  msg.precision(5);
  msg << command.body << ": " << nodes << " surface nodes (" << surface.area.sum() << " m^2), " << modes
      << " modes, " << welch.averages() << " averages of " << n << " samples (" << df << " Hz); ERP "
      << total_erp << " W (" << level_db(total_erp, power_ref) << " dB re 1e-12 W)";
  log.info(msg.str());

  std::vector<TextOutput> csvs;
  if (common.csv_dir) {
    Eigen::VectorXd nominal(erp_level.size()), center(erp_level.size());
    for (std::size_t b = 0; b < bands.size(); ++b) {
      nominal[static_cast<Eigen::Index>(b)] = bands[b].nominal_hz;
      center[static_cast<Eigen::Index>(b)] = bands[b].center_hz;
    }
    std::vector<std::string> header = {"nominal_hz", "center_hz", "erp_w", "erp_level_db",
                                       "velocity_level_db"};
    std::vector<Eigen::VectorXd> columns = {nominal, center, erp_band, erp_level, velocity_level};
    for (std::size_t r = 0; r < command.regions.size(); ++r) {
      const std::string& name = sanitize_name(command.regions[r].name);
      header.push_back("erp_level_db_" + name);
      columns.push_back(levels(band.col(2 + 2 * static_cast<Eigen::Index>(r)), power_ref, false));
      header.push_back("velocity_level_db_" + name);
      columns.push_back(levels(band.col(3 + 2 * static_cast<Eigen::Index>(r)), velocity_ref, true));
    }
    std::vector<const Eigen::VectorXd*> ptrs;
    for (const Eigen::VectorXd& c : columns) ptrs.push_back(&c);
    write_csv(csvs, *common.csv_dir / csv_names[0], header, ptrs);
    const Eigen::VectorXd density = densities.col(0), bin = density * welch.enbw_hz(),
                          vpsd = densities.col(1);
    write_csv(csvs, *common.csv_dir / csv_names[1],
              {"frequency_hz", "erp_density_w_per_hz", "erp_bin_w", "velocity_psd_m2_per_s2_hz"},
              {&f, &density, &bin, &vpsd});
  }
  commit_outputs(out, csvs);
}

namespace {

class ErpAnalysis final : public Analysis {
 public:
  void add_options(CLI::App& e, CliShared& shared) override {
    e.add_option("RESULTS", command_.results, "solve's results file (HDF5)")->required();
    e.add_option("--superelement", command_.superelement,
                 "the body's superelement file, with its exported /surface")
        ->required();
    e.add_option("--body", command_.body, "the flexible body in the results (/bodies/<name>)")->required();
    add_output_options(e, command_.common, shared);
    e.add_option("--velocity-reference", command_.common.velocity_reference,
                 "dB reference of velocity: engine (5e-8 m/s, default) or iso (1e-9 m/s, ISO 1683)")
        ->check(CLI::IsMember({"engine", "iso"}));
    add_time_window(e, command_.common);
    e.add_option("--window", window_, "rectangular, hann (default), hamming, flattop, blackman-harris");
    e.add_option("--resolution", command_.resolution_hz,
                 "frequency resolution, Hz (default: one segment of the longest power of two of samples)")
        ->check(CLI::PositiveNumber);
    e.add_option("--segment", command_.segment_length, "segment length, samples (overrides --resolution)")
        ->check(CLI::PositiveNumber);
    e.add_option("--overlap", command_.overlap, "segment overlap fraction in [0, 1) (default 0.5)");
    e.add_option("--fraction", command_.fraction, "b of 1/b-octave bands (default 3)")
        ->check(CLI::Range(1, 48));
    e.add_option("--fmin", command_.fmin_hz,
                 "lowest band, Hz (default: 20 or the lowest band at least 2 bins wide)")
        ->check(CLI::PositiveNumber);
    e.add_option("--fmax", command_.fmax_hz, "highest band, Hz (default: 10000 or the highest below Nyquist)")
        ->check(CLI::PositiveNumber);
    e.add_option("--rho", command_.density_kg_m3, "fluid density, kg/m^3 (default 1.204: air at 20 C)")
        ->check(CLI::PositiveNumber);
    e.add_option("--sound-speed", command_.sound_speed_m_s,
                 "speed of sound, m/s (default 343.2: air at 20 C)")
        ->check(CLI::PositiveNumber);
    e.add_option("--region", regions_,
                 "NAME=xmin,ymin,zmin,xmax,ymax,zmax: a surface region (box, m, component axes); repeatable");
    e.add_flag("--node-spectra", command_.node_spectra, "also write the velocity PSD of every surface node");
    e.add_flag("--include-rigid", command_.include_rigid,
               "add the frame's rigid-body motion (the block on its mounts) to the elastic normal velocity");
  }

  void run(const Logger& log, int argc, const char* const* argv) override {
    command_.window = parse_window(window_);
    for (const std::string& r : regions_) command_.regions.push_back(parse_region(r));
    run_erp(command_, log, argc, argv);
  }

  std::filesystem::path output() const override { return command_.common.output; }

 private:
  ErpCommand command_;
  std::string window_ = "hann";
  std::vector<std::string> regions_;
};

}  // namespace

std::unique_ptr<Analysis> make_erp_analysis() {
  return std::make_unique<ErpAnalysis>();
}

}  // namespace nvh::postproc
