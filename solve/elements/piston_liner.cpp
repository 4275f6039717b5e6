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
//
// The elasto-hydrodynamic liner (optional key `liner`, docs/bearing.md section 17): N markers on the liner's
// surface (markers 2 .. N+1, after i and j), e.g. points of a flexible block, forming a grid of axial levels
// x angles in j's frame at the initial state (Z_k = z_j . q_k, theta_k from x_j towards w, q_k = p_k - p_j).
// Marker k's radial displacement and rate (relative to j, outwards):
//   u_k  = |P q_k| - rho_k0,  P = 1 - z_j z_j^T, rho_k0 = |P q_k| at the initial state
//   u_k' = n_k . (v_k - v_j - w_j x q_k),   n_k = P q_k / |P q_k|
// The film at a point (theta, y) of the skirt sees the liner at Z = zeta + y, zeta = z_j . (p_i - p_j) (the
// piston's tilt neglected there): u(Z, theta) = sum_k W_k(Z, theta) u_k, bilinear in (Z, theta) over the grid
// (periodic around; held constant beyond the axial ends: `liner_uncovered` counts those points). Film and
// squeeze (eq. 12 with the liner's moving profile, in the piston's frame):
//   h   = (rigid-liner h) + u,    dh/dt = (piston's part) + sum_k W_k u_k' + V sum_k dW_k/dZ u_k
// Forces: each cell's pressure p_c (film + asperities) times its area pushes the liner outwards; it goes to
// the markers by the transpose of the same interpolation at the cells' centres, F_k = n_k sum_c W_k(c) p_c
// dA, and the liner's slope pushes the piston along the axis by F_s = sum_c p_c (du/dZ)_c dA (added to
// F_friction). j gets the rest of the reaction: -(F + sum F_k), -(T + d x F + sum q_k x F_k). The power of
// all wrenches is then F_side e'(0) - M tilt' + F_friction V + sum_k F_k . n_k u_k' = -(power_loss + d/dt of
// the asperity energy) with the film's power loss counting p dh/dt of the full dh/dt above.
// Jacobian with liner markers: the film's outputs and the N marker forces by central differences in the
// 5 inputs, zeta and each active marker's u_k and u_k' (those whose weights touch the skirt now), the chain
// rule to the marker columns analytic. Key `liner_jacobian`:
//   "linearized" (default): each difference is a linearized film (SkirtFilm::evaluate_linearized): one
//     factorization of the Reynolds system's Newton matrix at the state, reused for all columns, the
//     cavitated set held - dP/dq = -A0^-1 dM/dq (implicit function theorem), the residual's change dM/dq
//     by differences of one assembly; no Newton solve per column (docs/bearing.md section 17.6);
//   "differences": each difference a full film solve (2 per column; the reference of the test);
//   "none": the u_k, u_k' columns left out (zeta and the 5 inputs kept): a modified Newton for IDA.
// The grid of levels x angles clusters the markers within `liner_tolerance` (m; default 1e-6 R): the
// observation points of a meshed block snap to surface nodes, off the nominal grid by up to half an element.
#include <algorithm>
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

/// The film inputs (see the top of this file): the five of the rigid liner; with liner markers the axial
/// position zeta of the pin on the liner and each liner marker's radial displacement u_k and rate u_k'; with
/// skirt markers each skirt marker's radial displacement and rate.
struct FilmInputs {
  std::array<double, 5> u{};   // e_top, e_bottom, e_top', e_bottom', V
  double zeta = 0;             // m
  std::vector<double> lu, lr;  // m, m/s (empty: a rigid liner)
  std::vector<double> su, sr;  // m, m/s (empty: a rigid skirt)
  bool operator==(const FilmInputs&) const = default;
  bearing::SkirtKinematics kinematics() const { return {u[0], u[1], u[2], u[3], u[4]}; }
};

/// The element's scalar outputs at one state.
struct Outputs {
  bearing::SkirtResult film;
  double side = 0, moment = 0, friction = 0;  // N, N m, N (film + asperities, see the top)
  double power_loss = 0;                      // W
  std::vector<double> liner_force;            // N, f_k along n_k on liner marker k
  std::vector<double> skirt_force;            // N, f_k along n_k on skirt marker k (< 0: pushed inwards)
  double slope_force = 0;                     // N, F_s (in `friction`)
  double liner_max = 0;                       // m, largest |u| of the liner at the cells' centres
  double skirt_max = 0;                       // m, largest |u| of the skirt at the cells' centres
  double uncovered = 0;                       // share of the film's lattice points beyond the liner's ends
  bool ok = false;
};

/// A grid of surface markers - the liner's (axial levels x angles in j's frame) or the skirt's (in i's
/// frame) at the initial state - and its bilinear weights.
struct SurfaceGrid {
  std::vector<double> z, theta;  // ascending; theta in [theta_0, theta_0 + 2 pi)
  std::vector<int> marker;       // marker of (level a, angle b): marker[a + z.size() b]
  std::vector<double> rho0;      // m, each marker's initial distance from the axis
  int size() const { return static_cast<int>(rho0.size()); }
  /// Up to four (marker, W, dW/dZ) at (Z, theta); `outside`: Z beyond the axial ends (held constant).
  struct Weight {
    int k;
    double w, dw;
  };
  int weights(double Z, double th, std::array<Weight, 4>& out, bool& outside) const {
    const int nz = static_cast<int>(z.size()), nt = static_cast<int>(theta.size());
    int a0 = 0, a1 = 0;
    double t = 0, dt = 0;
    outside = false;
    if (nz > 1) {
      if (Z <= z.front()) {
        a0 = 0, a1 = 1, outside = Z < z.front();
      } else if (Z >= z.back()) {
        a0 = nz - 2, a1 = nz - 1, t = 1, outside = Z > z.back();
      } else {
        a1 = static_cast<int>(std::upper_bound(z.begin(), z.end(), Z) - z.begin()), a0 = a1 - 1;
        dt = 1 / (z[a1] - z[a0]), t = (Z - z[a0]) * dt;
      }
    }
    int b0 = 0, b1 = 0;
    double s = 0;
    if (nt > 1) {
      const double tw = th - 2 * std::numbers::pi * std::floor((th - theta[0]) / (2 * std::numbers::pi));
      b1 = static_cast<int>(std::upper_bound(theta.begin(), theta.end(), tw) - theta.begin());
      b0 = b1 - 1;
      const double end = b1 < nt ? theta[b1] : theta[0] + 2 * std::numbers::pi;
      if (b1 == nt) b1 = 0;
      s = std::clamp((tw - theta[b0]) / (end - theta[b0]), 0.0, 1.0);
    }
    out = {Weight{marker[a0 + nz * b0], (1 - t) * (1 - s), -dt * (1 - s)},
           Weight{marker[a1 + nz * b0], t * (1 - s), dt * (1 - s)},
           Weight{marker[a0 + nz * b1], (1 - t) * s, -dt * s}, Weight{marker[a1 + nz * b1], t * s, dt * s}};
    return 4;
  }
};

/// A surface marker's radial displacement u = |P q| - rho_0 from the axis z through `origin`, its rate
/// n . (v - v_o - w_o x q) in the frame of the marker `o` that carries the axis, its normal n = P q / |P q|,
/// and the derivatives of n by q and by o's rotation (P = 1 - z z^T, q = p - p_o).
struct Radial {
  double u = 0, rate = 0;
  Vec3 n, q;
  Mat3 dn_dq, dn_dth;
  Radial(const MarkerMotion& p, const MarkerMotion& o, const Vec3& z, double rho0) {
    q = p.position - o.position;
    const Vec3 pq = q - z * z.dot(q);
    const double rho = pq.norm();
    n = pq / rho;
    u = rho - rho0;
    rate = n.dot(p.velocity - o.velocity - o.angular_velocity.cross(q));
    const Mat3 proj = Mat3::Identity() - n * n.transpose();
    dn_dq = (proj - z * z.transpose()) / rho;
    dn_dth = (z.dot(q) * proj * skew(z) - z * z.cross(q).transpose()) / rho;
  }
};

class PistonLiner final : public ForceElement {
 public:
  /// How the Jacobian's columns of the surface markers are found (key `liner_jacobian`, see the top).
  enum class LinerJacobian { kLinearized, kDifferences, kNone };
  PistonLiner(bearing::SkirtSpec spec, bearing::FiniteSolverOptions options, double mu_asperity,
              double regularization_speed, SurfaceGrid grid = {},
              LinerJacobian liner_jacobian = LinerJacobian::kLinearized, SurfaceGrid skirt = {})
      : film_(std::move(spec), options),
        mu_(mu_asperity),
        v_s_(regularization_speed),
        grid_(std::move(grid)),
        skirt_(std::move(skirt)),
        liner_jacobian_(liner_jacobian) {
    const auto& s = film_.spec();
    s_top_ = s.skirt_top, s_bottom_ = s.skirt_top - s.skirt_length;
    nl_ = grid_.size(), ns_ = skirt_.size();
    if (nl_ + ns_ > 0) {
      const int lattice = (2 * s.cells_axial + 1) * (2 * s.cells_around + 1);
      field_.lattice.assign(film_.arcs(), std::vector<double>(lattice));
      field_.rate.assign(film_.arcs(), std::vector<double>(s.cells_axial * s.cells_around));
    }
    if (ns_ > 0) {  // the skirt's weights are fixed on the piston: once
      fill_stencil(skirt_, 0.0, skirt_stencil_);
      std::vector<char> on(ns_, 0);
      for (const auto& w : skirt_stencil_.lattice)
        for (const auto& e : w) on[e.k] = 1;
      for (int k = 0; k < ns_; ++k)
        if (on[k]) skirt_active_.push_back(k);
    }
  }
  std::string type() const override { return "piston-liner"; }
  int marker_count() const override { return 2 + nl_ + ns_; }

  FilmInputs inputs(const ElementInput& in) const {
    const MarkerMotion &i = in.markers[0], &j = in.markers[1];
    const Vec3 x = j.axes.col(0), z = j.axes.col(2), a = i.axes.col(2);
    const Vec3 d = i.position - j.position, dv = i.velocity - j.velocity;
    FilmInputs f;
    int k = 0;
    for (double s : {s_top_, s_bottom_}) f.u[k++] = x.dot(d + s * a);
    for (double s : {s_top_, s_bottom_})
      f.u[k++] = x.dot(dv + s * i.angular_velocity.cross(a) - j.angular_velocity.cross(d + s * a));
    f.u[4] = z.dot(dv - j.angular_velocity.cross(d));
    if (nl_ > 0) {
      f.zeta = z.dot(d);
      f.lu.resize(nl_), f.lr.resize(nl_);
      for (int m = 0; m < nl_; ++m) {
        const Radial r(in.markers[2 + m], j, z, grid_.rho0[m]);
        f.lu[m] = r.u, f.lr[m] = r.rate;
      }
    }
    if (ns_ > 0) {
      f.su.resize(ns_), f.sr.resize(ns_);
      for (int m = 0; m < ns_; ++m) {
        const Radial r(in.markers[2 + nl_ + m], i, a, skirt_.rho0[m]);
        f.su[m] = r.u, f.sr[m] = r.rate;
      }
    }
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
    const Outputs& o = outputs(inputs(in));
    const Vec3 x = j.axes.col(0), z = j.axes.col(2), a = i.axes.col(2);
    apply_at_i(in, out, o.side * x + o.friction * z, o.moment * x.cross(a), i.position);
    // the surface markers: F_k = f_k n_k, the rest of the reaction on j (liner) or i (skirt)
    for (int m = 0; m < nl_ + ns_; ++m) {
      const bool liner = m < nl_;
      const MarkerMotion& o_m = liner ? j : i;
      const Vec3 q = in.markers[2 + m].position - o_m.position, axis = liner ? z : a,
                 force = (liner ? o.liner_force[m] : o.skirt_force[m - nl_]) *
                         (q - axis * axis.dot(q)).normalized();
      Wrench& carrier = out.wrenches[liner ? 1 : 0];
      out.wrenches[2 + m].force = force;
      carrier.force -= force;
      carrier.torque -= q.cross(force);
    }
  }

  bool jacobian(const ElementInput& in, ElementJacobian& jac) const override;

  std::vector<Channel> channels() const override {
    std::vector<Channel> c = {{"min_film", "m"},         {"max_pressure", "Pa"},
                              {"side_force", "N"},       {"pin_moment", "N m"},
                              {"friction_force", "N"},   {"power_loss", "W"},
                              {"asperity_force", "N"},   {"oil_flow", "m^3/s"},
                              {"eccentricity_top", "m"}, {"eccentricity_bottom", "m"},
                              {"sliding_speed", "m/s"},  {"asperity_energy", "J"}};
    if (nl_ > 0)
      c.insert(c.end(), {{"liner_displacement", "m"}, {"liner_force", "N"}, {"liner_uncovered", "1"}});
    if (ns_ > 0) c.insert(c.end(), {{"skirt_displacement", "m"}, {"skirt_force", "N"}});
    return c;
  }
  void channel_values(const ElementInput& in, std::span<double> v) const override {
    const FilmInputs f = inputs(in);
    const Outputs& o = outputs(f);
    const bearing::SkirtResult& r = o.film;
    std::vector<double> values = {r.min_film, r.max_pressure, o.side,          o.moment,
                                  o.friction, o.power_loss,   r.asperity_load, r.flow_bottom + r.flow_top,
                                  f.u[0],     f.u[1],         f.u[4],          r.asperity_energy};
    auto sum = [](const std::vector<double>& x) {
      double s = 0;
      for (double e : x) s += e;
      return s;
    };
    if (nl_ > 0) values.insert(values.end(), {o.liner_max, sum(o.liner_force), o.uncovered});
    if (ns_ > 0) values.insert(values.end(), {o.skirt_max, sum(o.skirt_force)});
    for (std::size_t k = 0; k < v.size() && k < values.size(); ++k) v[k] = values[k];
  }
  /// Stored: the asperities' elastic energy; dissipated: power_loss (see the top).
  ElementEnergy energy(const ElementInput& in) const override {
    const Outputs& o = outputs(inputs(in));
    return {o.film.asperity_energy, o.power_loss};
  }

 private:
  /// The interpolation weights of a surface grid at the film's lattice points (all arcs, in fill_field's
  /// order) and at the cells' centres (compute's order), the grid's axial coordinate being the film's (along
  /// the piston from the pin) plus `offset`: zeta for the liner, 0 for the skirt.
  struct Stencil {
    double zeta = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::array<SurfaceGrid::Weight, 4>> lattice, centre;
    double uncovered = 0;  // share of the lattice points beyond the grid's axial ends
  };
  void fill_stencil(const SurfaceGrid& grid, double offset, Stencil& st) const {
    const auto& s = film_.spec();
    const int nx = s.cells_axial, nz = s.cells_around;
    const double dy = s.skirt_length / nx;
    st.lattice.resize(std::size_t(film_.arcs()) * (2 * nx + 1) * (2 * nz + 1));
    st.centre.resize(std::size_t(film_.arcs()) * nx * nz);
    int outside_count = 0, points = 0;
    auto lw = st.lattice.begin(), cw = st.centre.begin();
    for (int a = 0; a < film_.arcs(); ++a) {
      const double start = film_.angle(a, 0) - 0.5 * (film_.angle(a, 1) - film_.angle(a, 0));
      const double dth = film_.angle(a, 1) - film_.angle(a, 0);
      for (int k2 = 0; k2 <= 2 * nz; ++k2)
        for (int i2 = 0; i2 <= 2 * nx; ++i2) {
          bool outside = false;
          grid.weights(offset + s_bottom_ + 0.5 * i2 * dy, start + 0.5 * k2 * dth, *lw++, outside);
          outside_count += outside, ++points;
        }
      for (int kz = 0; kz < nz; ++kz)
        for (int i = 0; i < nx; ++i) {
          bool outside = false;
          grid.weights(offset + film_.axial_position(i), film_.angle(a, kz), *cw++, outside);
        }
    }
    st.uncovered = double(outside_count) / points;
    st.zeta = offset;
  }
  /// The liner's stencil for the pin at zeta: recomputed when zeta changes (the Jacobian's columns other than
  /// zeta's reuse it).
  const Stencil& stencil(double zeta) const {
    if (stencil_.zeta != zeta) fill_stencil(grid_, zeta, stencil_);
    return stencil_;
  }

  /// The surface field of the film (bearing::LinerField) for these inputs: u = u_liner - u_skirt on each
  /// arc's lattice, the surfaces' squeeze rate at the centres; returns the share of lattice points beyond the
  /// liner's axial ends.
  double fill_field(const FilmInputs& f) const {
    const auto& s = film_.spec();
    const int nx = s.cells_axial, nz = s.cells_around;
    const double V = f.u[4];
    const auto* lw = nl_ > 0 ? stencil(f.zeta).lattice.data() : nullptr;
    const auto* sw = ns_ > 0 ? skirt_stencil_.lattice.data() : nullptr;
    for (int a = 0; a < film_.arcs(); ++a)
      for (int k2 = 0; k2 <= 2 * nz; ++k2)
        for (int i2 = 0; i2 <= 2 * nx; ++i2) {
          double u = 0, slope = 0, rate = 0;
          if (lw)
            for (const auto& e : *lw++)
              u += e.w * f.lu[e.k], slope += e.dw * f.lu[e.k], rate += e.w * f.lr[e.k];
          if (sw)
            for (const auto& e : *sw++) u -= e.w * f.su[e.k], rate -= e.w * f.sr[e.k];
          field_.lattice[a][i2 + (2 * nx + 1) * k2] = u;
          if (i2 % 2 && k2 % 2) field_.rate[a][i2 / 2 + nx * (k2 / 2)] = rate + V * slope;  // eq. at the top
        }
    return nl_ > 0 ? stencil_.uncovered : 0.0;
  }

  /// `linearized`: the film's linearized evaluation about the state of film_.linearize() (the Jacobian's).
  Outputs compute(const FilmInputs& f, bool linearized = false) const {
    Outputs o;
    const bool ehl = nl_ + ns_ > 0;
    try {
      if (ehl) o.uncovered = fill_field(f);
      o.film = linearized ? film_.evaluate_linearized(f.kinematics(), ehl ? &field_ : nullptr)
                          : film_.evaluate(f.kinematics(), ehl ? &field_ : nullptr);
    } catch (const Error&) {
      film_.reset();
      const double nan = std::numeric_limits<double>::quiet_NaN();
      o.side = o.moment = o.friction = o.power_loss = nan;
      o.liner_force.assign(nl_, nan);
      o.skirt_force.assign(ns_, nan);
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
    if (ehl) {  // the cells' pressures back to the surface markers, the liner's slope's axial force on the
                // piston
      const auto& s = film_.spec();
      const int nx = s.cells_axial, nz = s.cells_around;
      o.liner_force.assign(nl_, 0.0);
      o.skirt_force.assign(ns_, 0.0);
      const auto* lw = nl_ > 0 ? stencil(f.zeta).centre.data() : nullptr;
      const auto* sw = ns_ > 0 ? skirt_stencil_.centre.data() : nullptr;
      for (int a = 0; a < film_.arcs(); ++a) {
        const double dA = R * (film_.angle(a, 1) - film_.angle(a, 0)) * L / nx;
        const std::vector<double>& p = film_.cell_pressure(a);
        for (int kz = 0; kz < nz; ++kz)
          for (int i = 0; i < nx; ++i) {
            const double load = p[i + nx * kz] * dA;
            if (lw) {
              double slope = 0, u = 0;
              for (const auto& e : *lw++)
                o.liner_force[e.k] += e.w * load, slope += e.dw * f.lu[e.k], u += e.w * f.lu[e.k];
              o.slope_force += load * slope;
              o.liner_max = std::max(o.liner_max, std::abs(u));
            }
            if (sw) {
              double u = 0;
              for (const auto& e : *sw++) o.skirt_force[e.k] -= e.w * load, u += e.w * f.su[e.k];
              o.skirt_max = std::max(o.skirt_max, std::abs(u));
            }
          }
      }
      o.friction += o.slope_force;
    }
    o.ok = true;
    return o;
  }

  /// The liner markers whose weights reach the film's lattice at this zeta (a superset: whole cells of the
  /// grid).
  std::vector<int> active(const FilmInputs& f) const {
    std::vector<char> on(nl_, 0);
    for (const auto& w : stencil(f.zeta).lattice)
      for (const auto& e : w) on[e.k] = 1;
    std::vector<int> list;
    for (int k = 0; k < nl_; ++k)
      if (on[k]) list.push_back(k);
    return list;
  }

  mutable bearing::SkirtFilm film_;  // mutable: its warm-start state
  double mu_ = 0, v_s_ = 0.01;
  double s_top_ = 0, s_bottom_ = 0;
  SurfaceGrid grid_;   // the liner's markers (markers 2 .. 1 + nl_)
  SurfaceGrid skirt_;  // the skirt's markers (markers 2 + nl_ .. 1 + nl_ + ns_)
  int nl_ = 0, ns_ = 0;
  LinerJacobian liner_jacobian_ = LinerJacobian::kLinearized;
  mutable bearing::LinerField field_;  // scratch of compute()
  struct Entry {
    std::optional<FilmInputs> inputs;
    Outputs out;
  };
  mutable Entry cache_[2];
  mutable Outputs scratch_;  // a linearized evaluation of jacobian()
  mutable Stencil stencil_;
  Stencil skirt_stencil_;
  std::vector<int> skirt_active_;  // the skirt markers whose weights reach the film
  mutable int newest_ = 0;
};

bool PistonLiner::jacobian(const ElementInput& in, ElementJacobian& jac) const {
  const MarkerMotion &mi = in.markers[0], &mj = in.markers[1];
  const FilmInputs f0 = inputs(in);
  const Outputs o0 = outputs(f0);
  if (!o0.ok) return false;
  const double c = film_.spec().radial_clearance, R = film_.spec().bore_radius;
  const int n = nl_ + ns_;
  const bool surfaces = liner_jacobian_ != LinerJacobian::kNone;
  const std::vector<int> act = nl_ > 0 && surfaces ? active(f0) : std::vector<int>{};
  const std::vector<int> sact = surfaces ? skirt_active_ : std::vector<int>{};
  // The film's linearization at f0 (a fresh solve there first: the cache may hold f0 from an older solve)
  bool linearized = false;
  if (n > 0 && liner_jacobian_ == LinerJacobian::kLinearized) {
    if (!compute(f0).ok) return false;
    linearized = film_.linearize();
  }
  // Columns of g: the 5 inputs, zeta (with liner markers), u_k of the active liner markers, their u_k', then
  // u_k and u_k' of the active skirt markers.
  const int na = static_cast<int>(act.size()), nsa = static_cast<int>(sact.size());
  const int first = nl_ > 0 ? 6 : 5, liner_u = first, liner_r = liner_u + na, skirt_u = liner_r + na,
            skirt_r = skirt_u + nsa, inputs_count = skirt_r + nsa;
  // g: d(F_side, M, F_friction, f_1 .. f_N) / d(inputs). The film's part (pressures, shear, asperity load
  // and side force) by central differences; the asperity friction composed here.
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(3 + n, inputs_count);
  double rate_scale = std::max({std::abs(f0.u[2]), std::abs(f0.u[3]), 1e-3 * std::abs(f0.u[4]), 1e-6});
  for (int k : act) rate_scale = std::max(rate_scale, std::abs(f0.lr[k]));
  for (int k : sact) rate_scale = std::max(rate_scale, std::abs(f0.sr[k]));
  const double t0 = std::tanh(f0.u[4] / v_s_);
  for (int col = 0; col < inputs_count; ++col) {
    double step = 0;
    std::array<FilmInputs, 2> f = {f0, f0};
    std::array<double*, 2> at{};
    for (int side = 0; side < 2; ++side) {
      FilmInputs& fs = f[side];
      double* value = nullptr;
      if (col < 5) {
        value = &fs.u[col];
        step = col < 2 ? 1e-6 * c : col < 4 ? 1e-6 * rate_scale : 1e-6 * std::max(std::abs(f0.u[4]), 1e-3);
      } else if (col < first) {
        value = &fs.zeta, step = 1e-7 * film_.spec().skirt_length;
      } else if (col < liner_r) {
        value = &fs.lu[act[col - liner_u]], step = 1e-6 * c;
      } else if (col < skirt_u) {
        value = &fs.lr[act[col - liner_r]], step = 1e-6 * rate_scale;
      } else if (col < skirt_r) {
        value = &fs.su[sact[col - skirt_u]], step = 1e-6 * c;
      } else {
        value = &fs.sr[sact[col - skirt_r]], step = 1e-6 * rate_scale;
      }
      at[side] = value;
      *value += side == 0 ? step : -step;
    }
    const double span = (*at[0] - *at[1]);
    std::array<Eigen::VectorXd, 2> y;
    for (int side = 0; side < 2; ++side) {
      const Outputs& o = linearized ? (scratch_ = compute(f[side], true)) : outputs(f[side]);
      if (!o.ok) return false;
      const bearing::SkirtResult& r = o.film;
      y[side].resize(3 + n);
      y[side][0] = r.side_force;
      y[side][1] = r.moment + mu_ * t0 * R * r.asperity_side_force;
      y[side][2] = r.friction_force - mu_ * t0 * r.asperity_load + o.slope_force;
      for (int k = 0; k < nl_; ++k) y[side][3 + k] = o.liner_force[k];
      for (int k = 0; k < ns_; ++k) y[side][3 + nl_ + k] = o.skirt_force[k];
    }
    g.col(col) = (y[0] - y[1]) / span;
  }
  const double dt_dv = (1 - t0 * t0) / v_s_;
  g(1, 4) += mu_ * dt_dv * R * o0.film.asperity_side_force;
  g(2, 4) -= mu_ * dt_dv * o0.film.asperity_load;

  // K: d(film inputs) / d(marker columns); i and j: [dp_i, dth_i, dv_i, dw_i, dp_j, dth_j, dv_j, dw_j], then
  // 12 per surface marker (3 each).
  const int cols = 12 * (2 + n);
  const Vec3 x = mj.axes.col(0), z = mj.axes.col(2), a = mi.axes.col(2);
  const Vec3 d = mi.position - mj.position, dv = mi.velocity - mj.velocity;
  const Vec3 &wi = mi.angular_velocity, &wj = mj.angular_velocity, w = wi - wj;
  Eigen::MatrixXd kin = Eigen::MatrixXd::Zero(inputs_count, cols);
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
  // the surface markers' radial motion: the liner's about j's axis z, the skirt's about i's axis a
  std::vector<Radial> radial;
  radial.reserve(n);
  for (int k = 0; k < n; ++k)
    radial.emplace_back(in.markers[2 + k], k < nl_ ? mj : mi, k < nl_ ? z : a,
                        k < nl_ ? grid_.rho0[k] : skirt_.rho0[k - nl_]);
  // a marker's rows u_k (row ru) and u_k' (row rr): its own columns ck and those of its axis' marker o (c0)
  auto radial_rows = [&](int ru, int rr, int k, int c0, const MarkerMotion& o, const Vec3& axis) {
    const Radial& r = radial[k];
    const int ck = 12 * (2 + k);
    // u_k = |P q| - rho_0: du/dq = n^T, du/dth_o = (axis . q) (n x axis)^T
    put(ru, ck, r.n), put(ru, c0, -r.n), put(ru, c0 + 3, axis.dot(r.q) * r.n.cross(axis));
    // u_k' = n . gk, gk = v_k - v_o - w_o x q; d(n . gk)/dq = gk^T dn/dq - n^T w_o~ (dn/dq symmetric)
    const Vec3 gk = in.markers[2 + k].velocity - o.velocity - o.angular_velocity.cross(r.q);
    const Eigen::RowVector3d dq = (r.dn_dq * gk).transpose() - r.n.transpose() * skew(o.angular_velocity);
    kin.block<1, 3>(rr, ck) += dq;
    kin.block<1, 3>(rr, c0) -= dq;
    kin.block<1, 3>(rr, c0 + 3) += gk.transpose() * r.dn_dth;
    put(rr, ck + 6, r.n), put(rr, c0 + 6, -r.n), put(rr, c0 + 9, r.n.cross(r.q));
  };
  if (nl_ > 0) put(5, 0, z), put(5, 12, -z), put(5, 15, z.cross(d));  // zeta = z . d
  for (int m = 0; m < na; ++m) radial_rows(liner_u + m, liner_r + m, act[m], 12, mj, z);
  for (int m = 0; m < nsa; ++m) radial_rows(skirt_u + m, skirt_r + m, nl_ + sact[m], 0, mi, a);
  // d(F_side, M, F_friction, f_k) / d(columns) = g kin; kin's rows of the surface markers (u_k, u_k') reach
  // only the marker's own and its axis' marker's columns: summed as such (the dense product costs 3 + N times
  // more)
  Eigen::MatrixXd dout = g.leftCols(first) * kin.topRows(first);
  for (int r = first; r < inputs_count; ++r) {
    const bool liner = r < skirt_u;
    const int k = liner ? act[(r - liner_u) % na] : nl_ + sact[(r - skirt_u) % nsa];
    for (int c0 : {liner ? 12 : 0, 12 * (2 + k)})
      for (int c = c0; c < c0 + 12; ++c)
        if (kin(r, c) != 0) dout.col(c) += kin(r, c) * g.col(r);
  }

  const Vec3 force = o0.side * x + o0.friction * z;
  const Vec3 axis = x.cross(a);
  Eigen::MatrixXd df = x * dout.row(0) + z * dout.row(2), dt = axis * dout.row(1);
  df.block<3, 3>(0, 15) -= skew(force);  // the force turns with the liner's axes
  // d(x_j x z_i): dth_j: (dth x x) x a = x (a . dth) - (a . x) dth; dth_i: x x (dth x a) = (x . a) dth - a (x
  // . dth)
  dt.block<3, 3>(0, 15) += o0.moment * (x * a.transpose() - a.dot(x) * Mat3::Identity());
  dt.block<3, 3>(0, 3) += o0.moment * (x.dot(a) * Mat3::Identity() - a * x.transpose());
  jacobian_at_i(in, jac, df, dt, force);
  // The surface markers (as point-set-contact): rows of k dF_k; rows of their axis' marker o (j for the
  // liner, i for the skirt) -dF_k and -q~ dF_k + F_k~ (dp_k - dp_o)
  auto& mat = jac.matrix;
  for (int k = 0; k < n; ++k) {
    const bool liner = k < nl_;
    const int ck = 12 * (2 + k), rk = 6 * (2 + k), co = liner ? 12 : 0, ro = liner ? 6 : 0;
    const Radial& r = radial[k];
    const double fk = liner ? o0.liner_force[k] : o0.skirt_force[k - nl_];
    if (fk == 0 && dout.row(3 + k).isZero(0)) continue;
    Eigen::MatrixXd dfk = r.n * dout.row(3 + k);
    dfk.block<3, 3>(0, ck) += fk * r.dn_dq;
    dfk.block<3, 3>(0, co) -= fk * r.dn_dq;
    dfk.block<3, 3>(0, co + 3) += fk * r.dn_dth;
    mat.block(rk, 0, 3, cols) += dfk;
    mat.block(ro, 0, 3, cols) -= dfk;
    mat.block(ro + 3, 0, 3, cols).noalias() -= skew(r.q) * dfk;
    const Mat3 fx = skew(fk * r.n);
    mat.block<3, 3>(ro + 3, ck) += fx;
    mat.block<3, 3>(ro + 3, co) -= fx;
  }
  if (!linearized) outputs(f0);  // leave the film's warm start at this state (the linearized: left there)
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

/// A surface's markers' grid from their initial positions (see the top): the liner's (`key` "liner", markers
/// first .. first + n - 1, in j's frame about the bore axis) or the skirt's ("skirt", in i's frame about the
/// piston axis, angles from x_j as the film's). Axial levels and angles clustered within `<key>_tolerance` (m
/// along the axis, that over R in rad around; default 1e-6 R), each level and angle the mean of its cluster,
/// angles cut at their widest gap; every (level, angle) exactly once. Errors name the key.
SurfaceGrid surface_grid(const input::Table& t, const ElementContext& c, const std::string& key, int first,
                         int n, double R) {
  const bool liner = key == "liner";
  const MarkerMotion &o = c.initial[liner ? 1 : 0], &j = c.initial[1];
  const Vec3 z = o.axes.col(2), x = (j.axes.col(0) - z * z.dot(j.axes.col(0))).normalized(), w = x.cross(z);
  const std::string& other = c.marker_bodies[liner ? 0 : 1];
  std::vector<double> zs(n), ths(n);
  SurfaceGrid g;
  g.rho0.resize(n);
  for (int k = 0; k < n; ++k) {
    const std::string which = key + " marker " + std::to_string(k + 1);
    if (c.marker_bodies[first + k] == other)
      t.fail(key, which + " is on the " + (liner ? "piston" : "liner") + "'s body '" + other + "'");
    const Vec3 q = c.initial[first + k].position - o.position;
    zs[k] = z.dot(q), ths[k] = std::atan2(w.dot(q), x.dot(q));
    g.rho0[k] = std::hypot(x.dot(q), w.dot(q));
    if (!(g.rho0[k] > 0.5 * R && g.rho0[k] < 2 * R))
      t.fail(key, which + " is " + std::to_string(g.rho0[k]) + " m from the " +
                      (liner ? "bore axis of marker j" : "piston axis of marker i") +
                      ": expected between R / 2 and 2 R (R = " + std::to_string(R) + " m), on the " +
                      (liner ? "liner's surface or wall" : "skirt's surface or wall"));
  }
  const double ztol = t.number_or(key + "_tolerance", 1e-6 * R, input::Range::closed(0.0, 0.5 * R)),
               ttol = ztol / R;
  {  // angles: cut the circle in the middle of the widest gap between markers (snapped points straddle +-pi)
    std::vector<double> v = ths;
    std::sort(v.begin(), v.end());
    double cut = v.back() - 2 * std::numbers::pi, gap = v.front() - cut;
    for (std::size_t k = 1; k < v.size(); ++k)
      if (v[k] - v[k - 1] > gap) gap = v[k] - v[k - 1], cut = v[k - 1];
    const double from = cut + 0.5 * gap;
    for (double& th : ths)
      th = from +
           std::fmod(std::fmod(th - from, 2 * std::numbers::pi) + 2 * std::numbers::pi, 2 * std::numbers::pi);
  }
  auto levels = [](std::vector<double> v, double tol) {  // clusters (gaps > tol between them), their means
    std::sort(v.begin(), v.end());
    std::vector<double> out;
    std::size_t first = 0;
    for (std::size_t k = 1; k <= v.size(); ++k)
      if (k == v.size() || v[k] - v[k - 1] > tol) {
        double sum = 0;
        for (std::size_t m = first; m < k; ++m) sum += v[m];
        out.push_back(sum / double(k - first)), first = k;
      }
    return out;
  };
  g.z = levels(zs, ztol), g.theta = levels(ths, ttol);
  const int nz = static_cast<int>(g.z.size()), nt = static_cast<int>(g.theta.size());
  if (nz * nt != n)
    t.fail(key, "the " + std::to_string(n) + " " + key +
                    " markers must form a grid of axial levels x angles in " + (liner ? "j" : "i") +
                    "'s frame: found " + std::to_string(nz) + " levels and " + std::to_string(nt) +
                    " angles");
  g.marker.assign(n, -1);
  auto find = [](const std::vector<double>& v, double e) {  // the nearest level
    const auto at = std::lower_bound(v.begin(), v.end(), e);
    if (at == v.begin()) return 0;
    if (at == v.end() || e - *(at - 1) < *at - e) return static_cast<int>(at - v.begin()) - 1;
    return static_cast<int>(at - v.begin());
  };
  for (int k = 0; k < n; ++k) {
    int& slot = g.marker[find(g.z, zs[k]) + nz * find(g.theta, ths[k])];
    if (slot >= 0)
      t.fail(key, key + " markers " + std::to_string(slot + 1) + " and " + std::to_string(k + 1) +
                      " are at the same axial level and angle");
    slot = k;
  }
  return g;
}

}  // namespace

void register_piston_liner(ElementRegistry& r) {
  r.add({"force",
         "piston-liner",
         "lubricated piston skirt on a rigid liner: 2D Reynolds (JFO) over the skirt with Greenwood-Tripp "
         "asperity "
         "contact; i the piston (pin axis origin, z_i towards the crown), j the liner (bore axis origin, z_j "
         "the "
         "bore axis, x_j the thrust direction); docs/bearing.md section 15; optional `liner`: markers on the "
         "liner's surface, a grid of axial levels x angles (elasto-hydrodynamic, section 17); optional "
         "`skirt`: "
         "markers on the skirt of a flexible piston, likewise (section 18)",
         {"i", "j", "liner[]?", "skirt[]?"},
         [](ElementContext& c) -> std::unique_ptr<ForceElement> {
           const auto& t = c.table;
           bearing::SkirtSpec spec = read_skirt(t);
           const double mu = t.number_or("mu_asperity", 0.1, input::Range::closed(0.0, 2.0));
           const double vs =
               t.number_or("friction_regularization_speed", 0.01, input::Range::closed(1e-6, 10.0));
           bearing::FiniteSolverOptions options;
           options.tolerance = t.number_or("film_tolerance", 1e-10, input::Range::closed(1e-14, 1e-4));
           const auto& bodies = c.marker_bodies;  // i, j, then the liner's and the skirt's markers
           if (bodies.size() > 2 &&
               bodies[0] == bodies[1])  // (the scene reader leaves this to a list element)
             t.fail("j", "markers i and j are on the same body: a force element connects two bodies");
           // the lists' lengths (the scene reader gives their markers in turn; a test may give the liner's
           // only)
           auto count = [&](const char* key) {
             return t.has(key) ? static_cast<int>(t.strings(key).size()) : 0;
           };
           const int ns = count("skirt"), nl = static_cast<int>(bodies.size()) - 2 - ns;
           SurfaceGrid liner, skirt;
           auto mode = PistonLiner::LinerJacobian::kLinearized;
           if (nl > 0) liner = surface_grid(t, c, "liner", 2, nl, spec.bore_radius);
           if (ns > 0) skirt = surface_grid(t, c, "skirt", 2 + nl, ns, spec.bore_radius);
           for (const char* key : {"liner_tolerance", "skirt_tolerance"}) t.accept(key);
           if (nl == 0 && t.has("liner_tolerance"))
             t.fail("liner_tolerance", "only with liner markers (`liner`)");
           if (ns == 0 && t.has("skirt_tolerance"))
             t.fail("skirt_tolerance", "only with skirt markers (`skirt`)");
           if (nl + ns > 0) {
             const std::string m = t.optional_choice("liner_jacobian", {"linearized", "differences", "none"})
                                       .value_or("linearized");
             mode = m == "differences" ? PistonLiner::LinerJacobian::kDifferences
                    : m == "none"      ? PistonLiner::LinerJacobian::kNone
                                       : PistonLiner::LinerJacobian::kLinearized;
           } else {
             t.accept("liner_jacobian");
             if (t.has("liner_jacobian"))
               t.fail("liner_jacobian", "only with liner or skirt markers (`liner`, `skirt`)");
           }
           return std::make_unique<PistonLiner>(std::move(spec), options, mu, vs, std::move(liner), mode,
                                                std::move(skirt));
         }});
}

}  // namespace nvh::solve
