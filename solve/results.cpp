#include "solve/results.hpp"

#include <numbers>
#include <set>

#include <hdf5.h>

#include "common/error.hpp"
#include "solve/fixed_axis_body.hpp"
#include "solve/flexible_rotor_body.hpp"

namespace nvh::solve {
namespace {

constexpr hsize_t kChunkValues = 131072;  // the largest chunk of a time history (1 MiB, HDF5's chunk cache)

// Every signal dataset of a scene: its path, its columns (0 = a 1-D vector) and its unit.
struct Signal {
  std::string path;
  int columns;
  std::string unit;
};

std::vector<Signal> signals_of(const Scene& s) {
  std::vector<Signal> out = {{"time", 0, "s"}, {"kinetic_energy", 0, "J"}};
  if (s.model.clock) out.push_back({"crank_angle_deg", 0, "deg"});
  for (const char* e : {"kinetic", "potential", "dissipated", "input", "balance"}) out.push_back({std::string("energy/") + e, 0, "J"});
  for (const auto& name : s.marker_names) {
    out.push_back({"markers/" + name + "/position", 3, "m"});
    out.push_back({"markers/" + name + "/velocity", 3, "m/s"});
    out.push_back({"markers/" + name + "/acceleration", 3, "m/s^2"});
  }
  if (s.output.bodies)
    for (const auto& b : s.model.bodies) {
      if (b->velocity_count() == 0) continue;
      out.push_back({"bodies/" + b->name() + "/position", 3, "m"});
      out.push_back({"bodies/" + b->name() + "/velocity", 3, "m/s"});
      if (b->kind() == "rigid" || b->kind() == "flexible" || b->kind() == "flexible-rotor") {
        out.push_back({"bodies/" + b->name() + "/euler_parameters", 4, "1"});
        out.push_back({"bodies/" + b->name() + "/angular_velocity", 3, "rad/s"});
      }
      if (flexible_part(*b) != nullptr) {  // the elastic coordinates and their
        const int n = flexible_part(*b)->modes();  // rates
        out.push_back({"bodies/" + b->name() + "/modal_coordinates", n, "superelement coordinates"});
        out.push_back({"bodies/" + b->name() + "/modal_velocities", n, "superelement coordinates / s"});
      }
      if (b->kind() == "flexible-rotor") {  // its angle and the support
        out.push_back({"bodies/" + b->name() + "/coordinate", 0, "rad"});
        out.push_back({"bodies/" + b->name() + "/coordinate_rate", 0, "rad/s"});
        out.push_back({"bodies/" + b->name() + "/support_force", 3, "N"});
        out.push_back({"bodies/" + b->name() + "/support_torque", 3, "N m"});
      }
      if (dynamic_cast<const FixedAxisBody*>(b.get()) != nullptr) {  // its coordinate and the support
        const bool rotor = b->kind() == "rotor";
        if (rotor) out.push_back({"bodies/" + b->name() + "/angular_velocity", 3, "rad/s"});
        out.push_back({"bodies/" + b->name() + "/coordinate", 0, rotor ? "rad" : "m"});
        out.push_back({"bodies/" + b->name() + "/coordinate_rate", 0, rotor ? "rad/s" : "m/s"});
        out.push_back({"bodies/" + b->name() + "/support_force", 3, "N"});
        out.push_back({"bodies/" + b->name() + "/support_torque", 3, "N m"});
      }
    }
  if (s.output.forces)
    for (const auto& f : s.model.forces) {
      out.push_back({"forces/" + f.name + "/force", 3, "N"});
      out.push_back({"forces/" + f.name + "/torque", 3, "N m"});
      for (const auto& c : f.element->channels()) out.push_back({"forces/" + f.name + "/" + c.name, 0, c.unit});
      for (const auto& st : f.element->states()) out.push_back({"forces/" + f.name + "/states/" + st.name, 0, st.unit});
    }
  if (s.output.joints)
    for (const auto& c : s.model.constraints) {
      out.push_back({"joints/" + c.name + "/reaction_force", 3, "N"});
      out.push_back({"joints/" + c.name + "/reaction_torque", 3, "N m"});
    }
  std::set<std::string> seen;
  for (const auto& sig : out)
    if (!seen.insert(sig.path).second)
      throw Error("two output channels of the scene share the path /" + sig.path +
                  " (an element's channel named like its force or torque, or two joints of one name)");
  return out;
}

std::string layout_signature(const Scene& s) {
  std::string sig = std::to_string(s.model.size());
  for (const auto& x : signals_of(s)) sig += "|" + x.path + ":" + std::to_string(x.columns);
  return sig;
}

}  // namespace

void result_datasets(const Scene& scene, std::vector<std::string>& paths, std::vector<int>& columns) {
  paths.clear();
  columns.clear();
  for (const auto& sig : signals_of(scene)) {
    paths.push_back(sig.path);
    columns.push_back(sig.columns);
  }
}

ResultsWriter ResultsWriter::create(const std::filesystem::path& path, const Scene& scene,
                                    const Provenance& provenance, const Checkpoint& start) {
  {
    h5::File file = h5::File::create(path);
    h5::Group root = file.root();
    root.set_attribute("format", kResultsFormat);
    root.set_attribute("format_version", kResultsFormatVersion);
    root.set_attribute("status", "running");
    root.set_attribute("scene", scene.name);
    root.set_attribute("sample_rate_hz", scene.output.sample_rate_hz);
    root.set_attribute("integrator", scene.integrator.method);
    root.set_attribute("layout", layout_signature(scene));
    write_provenance(root, provenance);
    for (const auto& sig : signals_of(scene)) {
      // A chunk holds one flush of samples (chunk_samples rows; halved while over 128 Ki values), so each
      // chunk is compressed once or twice (a flush that ends a step a few samples past a chunk's end
      // touches the next one). HDF5's automatic 16 Ki-row chunks were compressed again, whole, at every
      // flush that added to them: 2.6 x the deflate work on the valvetrain at 20 kHz (docs/results-format.md).
      const hsize_t columns = std::max(1, sig.columns);
      hsize_t rows = static_cast<hsize_t>(scene.output.chunk_samples);
      while (rows * columns > kChunkValues && rows % 2 == 0) rows /= 2;
      const h5::Chunking chunking{sig.columns == 0 ? std::vector<hsize_t>{rows} : std::vector<hsize_t>{rows, columns},
                                  scene.output.compression};  // gzip level ([output] compression)
      auto ds = sig.columns == 0 ? root.create_appendable_vector(sig.path, chunking)
                                 : root.create_appendable(sig.path, sig.columns, chunking);
      ds.set_attribute("unit", sig.unit);
    }
    if (!scene.marker_names.empty()) root.set_attribute("axes", "global", "markers");
    h5::Group cp = root.create_group("checkpoint");
    // The first checkpoint goes in before the file appears under its name, so there is never a results file
    // that --restart refuses (a run killed in its first moments left "running" without a checkpoint).
    const double no_samples = static_cast<double>(start.samples);  // 0 but for a steady-state result
    cp.create_appendable("y", scene.model.size())
        .append({start.y.data(), static_cast<std::size_t>(start.y.size())});
    cp.create_appendable("yp", scene.model.size())
        .append({start.yp.data(), static_cast<std::size_t>(start.yp.size())});
    cp.create_appendable_vector("samples").append({&no_samples, 1});
    cp.create_appendable_vector("time").append({&start.time, 1});
    std::vector<std::string> states;
    for (int k = 0; k < scene.model.size(); ++k) states.push_back(scene.model.describe_state(k));
    cp.write("state_names", states);
    file.commit();
  }
  ResultsWriter w;
  w.file_ = std::make_unique<h5::File>(h5::File::open_append(path));
  w.open_datasets(scene);
  return w;
}

ResultsWriter ResultsWriter::reopen(const std::filesystem::path& path, const Scene& scene, Checkpoint& checkpoint) {
  ResultsWriter w;
  w.file_ = std::make_unique<h5::File>(h5::File::open_append(path));
  h5::Group root = w.file_->root();
  if (!root.has_attribute("format") || root.string_attribute("format") != kResultsFormat)
    throw Error(path.string() + ": not a results file of solve (no format = \"nvh-results\" attribute)");
  if (root.string_attribute("layout") != layout_signature(scene))
    throw Error(path.string() + ": written for another scene (its bodies, markers or elements differ): cannot "
                "restart from it");
  h5::Group cp = root.open_group("checkpoint");
  auto times = cp.open_appendable("time");
  if (times.rows() == 0) throw Error(path.string() + ": has no checkpoint to restart from");
  const Eigen::VectorXd t = cp.read_vector("time");
  const Eigen::VectorXd samples = cp.read_vector("samples");
  const Eigen::MatrixXd y = cp.read_matrix("y"), yp = cp.read_matrix("yp");
  const Eigen::Index last = std::min({t.size(), samples.size(), y.rows(), yp.rows()}) - 1;
  if (last < 0) throw Error(path.string() + ": its checkpoint is incomplete");
  checkpoint.time = t[last];
  checkpoint.samples = static_cast<long>(samples[last]);
  checkpoint.y = y.row(last).transpose();
  checkpoint.yp = yp.row(last).transpose();
  w.open_datasets(scene);
  for (auto& c : w.channels_) c.dataset.truncate(static_cast<hsize_t>(checkpoint.samples));
  w.samples_ = w.written_ = checkpoint.samples;
  root.set_attribute("status", "running");
  return w;
}

void ResultsWriter::open_datasets(const Scene& scene) {
  h5::Group root = file_->root();
  channels_.clear();
  for (const auto& sig : signals_of(scene))
    channels_.push_back(Channel{root.open_appendable(sig.path), {}, sig.path, std::max(1, sig.columns)});
  channel_counts_.clear();
  for (const auto& f : scene.model.forces) channel_counts_.push_back(f.element->channels().size());
  if (root.has_attribute("reference", "energy")) energy_reference_ = root.double_attribute("reference", "energy");
}

void ResultsWriter::add_sample(double t, const Scene& scene, const Eigen::VectorXd& y, const Eigen::VectorXd& yp) {
  // Values go to the channels in the order of signals_of (no paths built per sample).
  const Model& m = scene.model;
  std::size_t next = 0;
  auto put = [&](const auto& v) {
    auto& b = channels_[next++].buffer;
    for (Eigen::Index k = 0; k < v.size(); ++k) b.push_back(v[k]);
  };
  auto put1 = [&](double v) { channels_[next++].buffer.push_back(v); };
  put1(t);
  const EnergyBalance e = m.energy(t, y.data(), yp.data());
  put1(e.kinetic);
  if (m.clock) put1(m.clock_angle(y.data()) * 180.0 / std::numbers::pi);
  const double total = e.kinetic + e.potential + e.dissipated - e.input;
  if (!energy_reference_) {  // the balance is measured from the first sample of the run
    energy_reference_ = total;
    file_->root().set_attribute("reference", total, "energy");
  }
  for (double v : {e.kinetic, e.potential, e.dissipated, e.input, total - *energy_reference_}) put1(v);
  for (const auto& ref : scene.output_markers) {
    const MarkerMotion mm = m.marker_motion(ref, y.data());
    put(mm.position);
    put(mm.velocity);
    put(m.marker_acceleration(ref, y.data(), yp.data()));
  }
  if (scene.output.bodies)
    for (std::size_t b = 0; b < m.bodies.size(); ++b) {
      const auto& body = *m.bodies[b];
      if (body.velocity_count() == 0) continue;
      const auto q = m.positions(static_cast<int>(b), y.data());
      const auto w = m.velocities(static_cast<int>(b), y.data());
      const auto* fixed = dynamic_cast<const FixedAxisBody*>(&body);
      const Vec3 reference = body.reference_position(q);
      put(reference);
      if (fixed) {
        put(fixed->reference_velocity(q, w));
        if (body.kind() == "rotor") put(Vec3(w[0] * fixed->axis()));
        put1(q[0]);
        put1(w[0]);
        const int bi = static_cast<int>(b);
        Vec3 force, torque;  // about the centre of mass, the reference point of sliders and rotors
        m.applied_wrench(bi, t, y.data(), yp.data(), reference, force, torque);
        const std::span<const double> wdot(yp.data() + m.body_offset(bi) + body.position_count(), 1);
        const SupportWrench s = fixed->support_wrench(q, w, wdot, m.gravity, force, torque);
        put(s.force);
        put(s.torque);
        continue;
      }
      if (const auto* rotor = dynamic_cast<const FlexibleRotorBody*>(&body)) {
        const Eigen::Index n = rotor->modes();
        put(Vec3::Zero());  // the pivot's velocity
        put(rotor->euler_parameters(q[0]));
        put(Vec3(w[0] * rotor->axis()));
        put(Eigen::Map<const Eigen::VectorXd>(q.data() + 1, n));
        put(Eigen::Map<const Eigen::VectorXd>(w.data() + 1, n));
        put1(q[0]);
        put1(w[0]);
        const int bi = static_cast<int>(b);
        Vec3 force, torque;  // about the pivot, the reference point
        m.applied_wrench(bi, t, y.data(), yp.data(), reference, force, torque);
        const std::span<const double> wdot(yp.data() + m.body_offset(bi) + body.position_count(),
                                           body.velocity_count());
        const SupportWrench s = rotor->support_wrench(q, w, wdot, m.gravity, force, torque);
        put(s.force);
        put(s.torque);
        continue;
      }
      put(Eigen::Map<const Vec3>(w.data()));
      if (body.kind() == "rigid" || body.kind() == "flexible") {
        put(Eigen::Map<const Vec4>(q.data() + 3));
        put(Vec3(body.rotation(q) * Eigen::Map<const Vec3>(w.data() + 3)));
      }
      if (body.kind() == "flexible") {
        const Eigen::Index n = body.position_count() - 7;
        put(Eigen::Map<const Eigen::VectorXd>(q.data() + 7, n));
        put(Eigen::Map<const Eigen::VectorXd>(w.data() + 6, n));
      }
    }
  if (scene.output.forces) {
    std::vector<MarkerMotion>& markers = motions_;
    for (std::size_t fi = 0; fi < m.forces.size(); ++fi) {
      const ForceEntry& f = m.forces[fi];
      const ElementInput in = m.element_input(f, t, y.data(), yp.data(), markers);
      wrenches_.assign(f.markers.size(), Wrench{});
      state_rows_.assign(f.state_count, 0.0);
      ElementOutput out{wrenches_, state_rows_};
      f.element->evaluate(in, out);
      // the resultant of the first markers' wrenches at marker 0's origin (force_element.hpp: resultant_markers)
      Wrench total = wrenches_[0];
      for (int k = 1; k < f.element->resultant_markers(); ++k) {
        total.force += wrenches_[k].force;
        total.torque += wrenches_[k].torque + (in.markers[k].position - in.markers[0].position).cross(wrenches_[k].force);
      }
      put(total.force);
      put(total.torque);
      values_.assign(channel_counts_[fi], 0.0);
      f.element->channel_values(in, values_);
      for (double v : values_) put1(v);
      for (double z : in.z) put1(z);
    }
  }
  if (scene.output.joints)
    for (std::size_t c = 0; c < m.constraints.size(); ++c) {
      Vec3 force, torque;
      m.reaction(static_cast<int>(c), t, y.data(), force, torque);
      put(force);
      put(torque);
    }
  if (next != channels_.size()) throw Error("results: internal error, the sample does not fill the channels");
  ++samples_;
}

void ResultsWriter::flush_samples() {
  for (auto& c : channels_) {
    c.dataset.append(c.buffer);
    c.buffer.clear();
    c.dataset.flush();
  }
  written_ = samples_;
}

void ResultsWriter::flush(const Checkpoint& cp) {
  flush_samples();
  h5::Group g = file_->root().open_group("checkpoint");
  // Checkpoint rows: y and y' first, time and the sample count last (a restart reads the shortest).
  auto y = g.open_appendable("y");
  y.append({cp.y.data(), static_cast<std::size_t>(cp.y.size())});
  auto yp = g.open_appendable("yp");
  yp.append({cp.yp.data(), static_cast<std::size_t>(cp.yp.size())});
  auto s = g.open_appendable("samples");
  const double n = static_cast<double>(samples_);
  s.append({&n, 1});
  auto t = g.open_appendable("time");
  t.append({&cp.time, 1});
  for (auto* d : {&y, &yp, &s, &t}) d->flush();
  file_->flush();
}

void ResultsWriter::finish(const std::string& status, const std::string& message, const IntegratorStatistics& st,
                           double wall_seconds) {
  h5::Group root = file_->root();
  h5::Group g = root.exists("solver/statistics") ? root.open_group("solver/statistics") : root.create_group("solver/statistics");
  g.set_attribute("steps", static_cast<std::int64_t>(st.steps));
  g.set_attribute("rejected_steps", static_cast<std::int64_t>(st.rejected_steps));
  g.set_attribute("newton_iterations", static_cast<std::int64_t>(st.newton_iterations));
  g.set_attribute("nonlinear_failures", static_cast<std::int64_t>(st.nonlinear_failures));
  g.set_attribute("jacobian_evaluations", static_cast<std::int64_t>(st.jacobian_evaluations));
  g.set_attribute("linear_solves", static_cast<std::int64_t>(st.linear_solves));
  g.set_attribute("residual_evaluations", static_cast<std::int64_t>(st.residual_evaluations));
  g.set_attribute("events", static_cast<std::int64_t>(st.events));
  g.set_attribute("last_order", st.last_order);
  g.set_attribute("last_step_s", st.last_step);
  for (std::size_t k = 0; k < st.steps_at_order.size(); ++k)
    g.set_attribute("steps_at_order_" + std::to_string(k + 1),
                    static_cast<std::int64_t>(st.steps_at_order[k]));
  g.set_attribute("wall_residual_s", st.cpu_residual_s);
  g.set_attribute("wall_jacobian_s", st.cpu_jacobian_s);
  if (!st.linear_solver.empty()) g.set_attribute("linear_solver", st.linear_solver);
  g.set_attribute("wall_linear_algebra_and_other_s", st.cpu_factorization_s);
  g.set_attribute("wall_s", wall_seconds);
  // Per unknown (the order of /checkpoint/state_names): the accepted steps it held the error test in.
  if (!st.error_test_steps.empty() && !g.exists("error_test_steps")) {
    std::vector<std::int64_t> held(st.error_test_steps.begin(), st.error_test_steps.end());
    g.write("error_test_steps", std::span<const std::int64_t>(held));
  }
  root.set_attribute("status", status);
  root.set_attribute("message", message);
  // Checked: the run's failure handler reports a status that did not reach the disk (a full disk).
  try {
    file_->flush();
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + " (the status \"" + status + "\" did not reach the file)");
  }
}

void ResultsWriter::set_drift(double position, double velocity) {
  h5::Group g = file_->root().open_group("solver/statistics");
  g.set_attribute("max_position_drift", position);
  g.set_attribute("max_velocity_drift", velocity);
  file_->flush();
}

int ResultsWriter::dataset_index(const std::string& path) const {
  for (std::size_t i = 0; i < channels_.size(); ++i)
    if (channels_[i].path == path) return static_cast<int>(i);
  return -1;
}

std::span<const double> ResultsWriter::last_sample(int index) const {
  const Channel& c = channels_.at(static_cast<std::size_t>(index));
  const auto w = static_cast<std::size_t>(c.width);
  if (c.buffer.size() < w) throw Error("results: internal error, no buffered sample of /" + c.path);
  return {c.buffer.data() + c.buffer.size() - w, w};
}

void ResultsWriter::append_rows(const h5::Group& source, hsize_t first, hsize_t end) {
  flush_samples();
  std::vector<double> rows;
  for (auto& c : channels_) {  // only the kept rows are read (a hyperslab): the history may be large
    const auto w = static_cast<hsize_t>(c.width);
    rows.resize((end - first) * w);
    const hid_t ds = H5Dopen2(source.id(), c.path.c_str(), H5P_DEFAULT);
    const hid_t space = ds < 0 ? -1 : H5Dget_space(ds);
    const int rank = space < 0 ? -1 : H5Sget_simple_extent_ndims(space);
    hsize_t dims[2] = {0, 0};
    if (rank >= 1) H5Sget_simple_extent_dims(space, dims, nullptr);
    const hsize_t start[2] = {first, 0}, count[2] = {end - first, w};
    const hid_t memory = H5Screate_simple(rank, count, nullptr);
    const bool ok = rank >= 1 && dims[0] >= end &&
                    H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr) >= 0 &&
                    H5Dread(ds, H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, rows.data()) >= 0;
    for (hid_t id : {memory, space})
      if (id >= 0) H5Sclose(id);
    if (ds >= 0) H5Dclose(ds);
    if (!ok)
      throw Error("results: cannot read the rows " + std::to_string(first) + " to " + std::to_string(end) +
                  " of /" + c.path + " (the kept cycles)");
    c.dataset.append(rows);
    c.dataset.flush();
  }
  samples_ = written_ = samples_ + static_cast<long>(end - first);
  if (source.has_attribute("reference", "energy")) {
    energy_reference_ = source.double_attribute("reference", "energy");
    file_->root().set_attribute("reference", *energy_reference_, "energy");
  }
  file_->flush();
}

}  // namespace nvh::solve
