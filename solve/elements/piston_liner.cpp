// The piston-liner force element, `[[force]] type = "piston-liner"`: the lubricated piston skirt on a rigid
// liner (issue 14, item 2). The film is solve/bearing's SkirtFilm (2D Reynolds over the skirt with JFO
// cavitation, wedge and squeeze terms, barrel and ovality, partial flooding; eq. 12 of the engine paper,
// ../shared/papers/000_*.txt) with the Greenwood-Tripp asperity contact (bearing/asperity_contact.hpp) on a
// film floor, so that one law covers full film, mixed lubrication and hard contact
// (docs/bearing.md, section 15).
//
// Markers. i: the piston, origin on the piston axis at the pin axis, z_i along the piston axis towards the
// crown. j: the liner (ground or the block), origin on the bore axis, z_j the bore axis (towards the crown),
// x_j the thrust direction (in the plane of the conrod's swing); the pin axis is w = x_j x z_j = -y_j. With
// d = p_i - p_j, d' = v_i - v_j, a = z_i and s the position along the piston axis (s = 0 at the pin):
//   e(s)  = x_j . (d + s a)                                    lateral displacement of the piston axis (m)
//   e'(s) = x_j . (d' + s w_i x a - w_j x (d + s a))           its rate in the liner's frame (m/s)
//   V     = z_j . (d' - w_j x d)                               axial sliding speed, piston against liner
//   (m/s)
// (w_i, w_j the angular velocities), at the skirt's top edge s = skirt_top and bottom edge skirt_top - L: the
// five film inputs e_top, e_bottom, e_top', e_bottom', V. Out-of-plane motion - along the pin axis, and the
// tilt about x_j - is not modelled by the film: only the projection on the plane (x_j, z_j) counts; a scene
// keeps the piston in that plane (its pin joint does).
//
// Forces on the piston, applied at p_i (the liner gets the reaction, apply_at_i):
//   F = F_side x_j + F_friction z_j,    T = M (x_j x z_i)     (|x_j x z_i| = 1 for a piston in the plane)
//   F_side     = SkirtResult::side_force (film and asperity pressures)
//   M          = SkirtResult::moment + mu_a t(V) R F_side,asperity              (about the pin axis)
//   F_friction = SkirtResult::friction_force - mu_a t(V) W_a                    (hydrodynamic shear +
//   asperity)
// with W_a the asperity load, F_side,asperity the asperities' side force, and t(V) = tanh(V / v_s) the
// regularized sign of the sliding speed (Coulomb friction on the asperities, v_s =
// friction_regularization_speed). The moment's axis x_j x z_i makes the wrenches' power exactly F_side e'(0)
// - M tilt' + F_friction V with tilt' = d/dt (x_j . z_i) = (e_top' - e_bottom') / L, the rates the film sees.
//
// Energy: the asperities store u(h) (asperity_contact.hpp); the dissipated power is the rest of the wrenches'
// work, power_loss = film power loss + mu_a t(V) W_a V + (M_shear + mu_a t(V) R F_side,asperity) tilt', so
// that the run's energy balance closes (the film's own power loss counts the shear at the sliding speed V;
// the last term is the shear moment's work on the tilt).
//
// Jacobian: d(F_side, M, F_friction) / d(5 film inputs) by central differences of the film (10 warm-started
// evaluations), the asperity friction's derivative by the sliding speed analytically; the chain rule to the
// marker columns analytically (the derivatives of e, e', V above). Warm start and cache as the journal
// bearing (journal_bearing_element.cpp): SkirtFilm keeps its last solution (mutable), and the last two
// results are cached by their inputs. A film that cannot be solved returns a non-finite force: IDA cuts its
// step.
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "common/error.hpp"
#include "solve/bearing/skirt_film.hpp"
#include "solve/element_registry.hpp"
#include "solve/elements/builtin.hpp"

namespace nvh::solve {

namespace {

constexpr double kDeg = std::numbers::pi / 180;

/// The five film inputs (see the top of this file).
struct FilmInputs {
  std::array<double, 5> u{};  // e_top, e_bottom, e_top', e_bottom', V
  bool operator==(const FilmInputs&) const = default;
  bearing::SkirtKinematics kinematics() const { return {u[0], u[1], u[2], u[3], u[4]}; }
};

/// The element's scalar outputs at one state.
struct Outputs {
  bearing::SkirtResult film;
  double side = 0, moment = 0, friction = 0;  // N, N m, N (film + asperities, see the top)
  double power_loss = 0;                      // W
  bool ok = false;
};

class PistonLiner final : public ForceElement {
 public:
  PistonLiner(bearing::SkirtSpec spec, bearing::FiniteSolverOptions options, double mu_asperity,
              double regularization_speed)
      : film_(std::move(spec), options), mu_(mu_asperity), v_s_(regularization_speed) {
    const auto& s = film_.spec();
    s_top_ = s.skirt_top, s_bottom_ = s.skirt_top - s.skirt_length;
  }
  std::string type() const override { return "piston-liner"; }
  int marker_count() const override { return 2; }

  FilmInputs inputs(const MarkerMotion& i, const MarkerMotion& j) const {
    const Vec3 x = j.axes.col(0), z = j.axes.col(2), a = i.axes.col(2);
    const Vec3 d = i.position - j.position, dv = i.velocity - j.velocity;
    FilmInputs f;
    int k = 0;
    for (double s : {s_top_, s_bottom_}) f.u[k++] = x.dot(d + s * a);
    for (double s : {s_top_, s_bottom_})
      f.u[k++] = x.dot(dv + s * i.angular_velocity.cross(a) - j.angular_velocity.cross(d + s * a));
    f.u[4] = z.dot(dv - j.angular_velocity.cross(d));
    return f;
  }

  const Outputs& outputs(const FilmInputs& f) const {
    for (int n : {newest_, 1 - newest_})
      if (cache_[n].inputs && *cache_[n].inputs == f) return cache_[n].out;
    newest_ = 1 - newest_;
    Entry& e = cache_[newest_];
    e.inputs = f;
    e.out = compute(f);
    return e.out;
  }

  void evaluate(const ElementInput& in, ElementOutput& out) const override {
    const MarkerMotion &i = in.markers[0], &j = in.markers[1];
    const Outputs& o = outputs(inputs(i, j));
    const Vec3 x = j.axes.col(0), z = j.axes.col(2);
    apply_at_i(in, out, o.side * x + o.friction * z, o.moment * x.cross(i.axes.col(2)), i.position);
  }

  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override;

  std::vector<Channel> channels() const override {
    return {{"min_film", "m"},         {"max_pressure", "Pa"},
            {"side_force", "N"},       {"pin_moment", "N m"},
            {"friction_force", "N"},   {"power_loss", "W"},
            {"asperity_force", "N"},   {"oil_flow", "m^3/s"},
            {"eccentricity_top", "m"}, {"eccentricity_bottom", "m"},
            {"sliding_speed", "m/s"},  {"asperity_energy", "J"}};
  }
  void channel_values(const ElementInput& in, std::span<double> v) const override {
    const FilmInputs f = inputs(in.markers[0], in.markers[1]);
    const Outputs& o = outputs(f);
    const bearing::SkirtResult& r = o.film;
    const double values[] = {r.min_film, r.max_pressure, o.side,          o.moment,
                             o.friction, o.power_loss,   r.asperity_load, r.flow_bottom + r.flow_top,
                             f.u[0],     f.u[1],         f.u[4],          r.asperity_energy};
    for (std::size_t k = 0; k < v.size() && k < std::size(values); ++k) v[k] = values[k];
  }
  /// Stored: the asperities' elastic energy; dissipated: power_loss (see the top).
  ElementEnergy energy(const ElementInput& in) const override {
    const Outputs& o = outputs(inputs(in.markers[0], in.markers[1]));
    return {o.film.asperity_energy, o.power_loss};
  }

 private:
  Outputs compute(const FilmInputs& f) const {
    Outputs o;
    try {
      o.film = film_.evaluate(f.kinematics());
    } catch (const Error&) {
      film_.reset();
      const double nan = std::numeric_limits<double>::quiet_NaN();
      o.side = o.moment = o.friction = o.power_loss = nan;
      return o;
    }
    const bearing::SkirtResult& r = o.film;
    const double R = film_.spec().bore_radius, L = film_.spec().skirt_length;
    const double t = std::tanh(f.u[4] / v_s_), tilt_rate = (f.u[2] - f.u[3]) / L;
    o.side = r.side_force;
    const double m_friction = mu_ * t * R * r.asperity_side_force;
    o.moment = r.moment + m_friction;
    o.friction = r.friction_force - mu_ * t * r.asperity_load;
    o.power_loss =
        r.power_loss + mu_ * t * r.asperity_load * f.u[4] + (r.shear_moment + m_friction) * tilt_rate;
    o.ok = true;
    return o;
  }

  mutable bearing::SkirtFilm film_;  // mutable: its warm-start state
  double mu_ = 0, v_s_ = 0.01;
  double s_top_ = 0, s_bottom_ = 0;
  struct Entry {
    std::optional<FilmInputs> inputs;
    Outputs out;
  };
  mutable Entry cache_[2];
  mutable int newest_ = 0;
};

bool PistonLiner::jacobian(const ElementInput& in, ElementJacobian& jac) const {
  const MarkerMotion &mi = in.markers[0], &mj = in.markers[1];
  const FilmInputs f0 = inputs(mi, mj);
  const Outputs o0 = outputs(f0);
  if (!o0.ok) return false;
  const double c = film_.spec().radial_clearance, R = film_.spec().bore_radius;
  // g: d(F_side, M, F_friction) / d(e_top, e_bottom, e_top', e_bottom', V). The film's part (pressures,
  // shear, asperity load and side force) by central differences; the asperity friction composed here.
  Eigen::Matrix<double, 3, 5> g;
  const double rate_scale = std::max({std::abs(f0.u[2]), std::abs(f0.u[3]), 1e-3 * std::abs(f0.u[4]), 1e-6});
  const double t0 = std::tanh(f0.u[4] / v_s_);
  for (int col = 0; col < 5; ++col) {
    const double step = col < 2   ? 1e-6 * c
                        : col < 4 ? 1e-6 * rate_scale
                                  : 1e-6 * std::max(std::abs(f0.u[4]), 1e-3);
    std::array<bearing::SkirtResult, 2> r;
    std::array<double, 2> h{};
    for (int side = 0; side < 2; ++side) {
      FilmInputs f = f0;
      f.u[col] += side == 0 ? step : -step;
      h[side] = f.u[col] - f0.u[col];
      const Outputs& o = outputs(f);
      if (!o.ok) return false;
      r[side] = o.film;
    }
    const double span = h[0] - h[1];
    auto diff = [&](auto member) { return (r[0].*member - r[1].*member) / span; };
    using bearing::SkirtResult;
    g(0, col) = diff(&SkirtResult::side_force);
    g(1, col) = diff(&SkirtResult::moment) + mu_ * t0 * R * diff(&SkirtResult::asperity_side_force);
    g(2, col) = diff(&SkirtResult::friction_force) - mu_ * t0 * diff(&SkirtResult::asperity_load);
  }
  const double dt_dv = (1 - t0 * t0) / v_s_;
  g(1, 4) += mu_ * dt_dv * R * o0.film.asperity_side_force;
  g(2, 4) -= mu_ * dt_dv * o0.film.asperity_load;

  // K: d(film inputs) / d(marker columns) [dp_i, dth_i, dv_i, dw_i, dp_j, dth_j, dv_j, dw_j] (3 each).
  const Vec3 x = mj.axes.col(0), z = mj.axes.col(2), a = mi.axes.col(2);
  const Vec3 d = mi.position - mj.position, dv = mi.velocity - mj.velocity;
  const Vec3 &wi = mi.angular_velocity, &wj = mj.angular_velocity, w = wi - wj;
  Eigen::Matrix<double, 5, 24> kin = Eigen::Matrix<double, 5, 24>::Zero();
  auto put = [&](int row, int col, const Vec3& v) { kin.block<1, 3>(row, col) += v.transpose(); };
  int row = 0;
  for (double s : {s_top_, s_bottom_}) {  // e(s) = x . (d + s a)
    put(row, 0, x), put(row, 12, -x), put(row, 3, s * a.cross(x)), put(row, 15, x.cross(d + s * a));
    ++row;
  }
  for (double s : {s_top_, s_bottom_}) {  // e'(s) = x . q, q = d' + s w_i x a - w_j x r, r = d + s a
    const Vec3 r = d + s * a, q = dv + s * wi.cross(a) - wj.cross(r);
    put(row, 0, -x.cross(wj)), put(row, 12, x.cross(wj));
    put(row, 3, s * a.cross(x.cross(w))), put(row, 15, x.cross(q));
    put(row, 6, x), put(row, 18, -x);
    put(row, 9, s * a.cross(x)), put(row, 21, x.cross(r));
    ++row;
  }
  {  // V = z . (d' - w_j x d)
    const Vec3 gv = dv - wj.cross(d);
    put(4, 0, -z.cross(wj)), put(4, 12, z.cross(wj)), put(4, 15, z.cross(gv));
    put(4, 6, z), put(4, 18, -z), put(4, 21, z.cross(d));
  }
  const Eigen::Matrix<double, 3, 24> dout = g * kin;  // d(F_side, M, F_friction) / d(columns)

  const Vec3 force = o0.side * x + o0.friction * z;
  const Vec3 axis = x.cross(a);
  ElementRows df = zero_rows(jac), dt = zero_rows(jac);
  df.leftCols<24>() = x * dout.row(0) + z * dout.row(2);
  df.block<3, 3>(0, 15) -= skew(force);  // the force turns with the liner's axes
  dt.leftCols<24>() = axis * dout.row(1);
  // d(x_j x z_i): dth_j: (dth x x) x a = x (a . dth) - (a . x) dth; dth_i: x x (dth x a) = (x . a) dth - a (x
  // . dth)
  dt.block<3, 3>(0, 15) += o0.moment * (x * a.transpose() - a.dot(x) * Mat3::Identity());
  dt.block<3, 3>(0, 3) += o0.moment * (x.dot(a) * Mat3::Identity() - a * x.transpose());
  jacobian_at_i(in, jac, df, dt, force);
  outputs(f0);  // leave the film's warm start at this state
  return true;
}

bearing::SkirtSpec read_skirt(const input::Table& t) {
  using input::Range;
  bearing::SkirtSpec s;
  s.name = t.path().empty() ? "piston-liner" : t.path();
  const auto radius = t.optional_number("bore_radius", Range::closed(1e-3, 5.0));
  const auto diameter = t.optional_number("diameter", Range::closed(2e-3, 10.0));
  if (radius.has_value() == diameter.has_value())
    t.fail("bore_radius", "expected either 'bore_radius' or 'diameter' (m), not both and not neither");
  s.bore_radius = radius ? *radius : 0.5 * *diameter;
  s.radial_clearance = t.number("radial_clearance", Range::closed(1e-7, 0.9 * s.bore_radius));
  s.skirt_length = t.number("skirt_length", Range::closed(1e-4, 10.0));
  s.skirt_top = t.number("skirt_top", Range::magnitude(10.0));
  t.accept("arcs_deg");
  if (t.has("arcs_deg")) {
    s.arcs.clear();
    for (const auto& row : t.number_rows("arcs_deg", 2, Range::closed(-720.0, 720.0)))
      s.arcs.push_back({row[0] * kDeg, row[1] * kDeg});
  }
  auto profile = [&](const char* key, double at_scale) {
    bearing::ProfileTable p;
    if (!t.has(key)) {
      t.accept(key);  // listed among the accepted keys of an error
      return p;
    }
    for (const auto& row : t.number_rows(key, 2, Range::magnitude(10.0)))
      p.at.push_back(row[0] * at_scale), p.value.push_back(row[1]);
    return p;
  };
  s.barrel = profile("barrel", 1.0);
  s.ovality = profile("ovality_deg", kDeg);
  s.viscosity = t.number("viscosity", Range::closed(1e-6, 1e5));
  const std::string cavitation =
      t.optional_choice("cavitation", {"jfo", "swift-stieber", "none"}).value_or("jfo");
  s.cavitation = cavitation == "jfo"             ? bearing::Cavitation::kJfo
                 : cavitation == "swift-stieber" ? bearing::Cavitation::kSwiftStieber
                                                 : bearing::Cavitation::kNone;
  s.fill_bottom = t.number_or("fill_bottom", 1.0, Range::closed(0.0, 1.0));
  s.fill_top = t.number_or("fill_top", 1.0, Range::closed(0.0, 1.0));
  s.cells_axial = static_cast<int>(t.optional_integer("cells_axial", Range::closed(2, 1000)).value_or(20));
  s.cells_around = static_cast<int>(t.optional_integer("cells_around", Range::closed(3, 1000)).value_or(12));
  // Asperity contact (Greenwood-Tripp): sigma, E' and either K or (sigma_beta_eta, sigma_over_beta).
  if (const auto sigma = t.optional_number("sigma", Range::closed(1e-9, 1.0))) {
    s.asperity.sigma = *sigma;
    s.asperity.modulus = t.number("modulus", Range::closed(1e6, 1e13));
    const auto K = t.optional_number("K", Range::closed(1e-12, 1.0));
    const auto sbe = t.optional_number("sigma_beta_eta", Range::closed(1e-6, 10.0));
    const auto sob = t.optional_number("sigma_over_beta", Range::closed(1e-8, 1.0));
    if (K.has_value() == (sbe.has_value() || sob.has_value()) || sbe.has_value() != sob.has_value())
      t.fail("K",
             "expected either the roughness constant 'K' or both 'sigma_beta_eta' and 'sigma_over_beta'");
    s.asperity.K = K ? *K : bearing::roughness_constant(*sbe, *sob);
  }
  // The film floor: by default half the roughness with asperity contact (the film then never closes), else
  // off
  s.film_floor =
      t.number_or("film_floor", 0.5 * s.asperity.sigma, Range::closed(0.0, 0.5 * s.radial_clearance));
  // A partially flooded skirt: the oil layer that the closing gap squeezes (docs/bearing.md section 15.4)
  s.oil_layer = t.number_or("oil_layer", 0.0, Range::closed(0.0, 10 * s.radial_clearance));
  // The spec's own checks (arcs that overlap, profile positions not ascending): located at the key they name
  try {
    bearing::validate(s);
  } catch (const Error& e) {
    const std::string m = e.what();
    for (const auto& [field, key] :
         {std::pair{"'arcs", "arcs_deg"}, std::pair{"'barrel", "barrel"},
          std::pair{"'ovality", "ovality_deg"}, std::pair{"'film_floor", "film_floor"}})
      if (m.find(field) != std::string::npos) t.fail(key, m);
    t.fail(m);
  }
  return s;
}

}  // namespace

void register_piston_liner(ElementRegistry& r) {
  r.add({"force",
         "piston-liner",
         "lubricated piston skirt on a rigid liner: 2D Reynolds (JFO) over the skirt with Greenwood-Tripp "
         "asperity "
         "contact; i the piston (pin axis origin, z_i towards the crown), j the liner (bore axis origin, z_j "
         "the "
         "bore axis, x_j the thrust direction); docs/bearing.md section 15",
         {"i", "j"},
         [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           const auto& t = c.table;
           bearing::SkirtSpec spec = read_skirt(t);
           const double mu = t.number_or("mu_asperity", 0.1, input::Range::closed(0.0, 2.0));
           const double vs =
               t.number_or("friction_regularization_speed", 0.01, input::Range::closed(1e-6, 10.0));
           bearing::FiniteSolverOptions options;
           options.tolerance = t.number_or("film_tolerance", 1e-10, input::Range::closed(1e-14, 1e-4));
           return std::make_unique<PistonLiner>(std::move(spec), options, mu, vs);
         }});
}

}  // namespace nvh::solve
