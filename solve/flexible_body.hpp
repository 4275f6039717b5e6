#pragma once
// Flexible bodies in a floating frame of reference, from condense's superelements (docs/scene-flexible.md).
//
// Coordinates: q = [r (3), p (4 Euler parameters), eta (n modal coordinates)], w = [v (3, global), omega (3,
// body axes), eta' (n)]. r and p place the superelement's own (component) frame; a material point at x in
// that frame is displaced elastically by u = S(x) eta, so it sits at r + A(p) (x + S(x) eta) in global axes.
//
// Equations of motion (A. A. Shabana, Dynamics of Multibody Systems, 3rd ed., Cambridge 2005, sec. 5.5,
// eq. 5.99-5.115, written in the quasi-velocities w): with s = x + S eta and J_P = [I, -A s~, A S] the
// Jacobian of a material point's velocity,
//   M(eta) w' + h(eta, w) = Q_gravity + Q_forces - [0; 0; K(omega) eta + D eta'],
//   M = int rho J_P^T J_P dV,   h = int rho J_P^T A (omega x (omega x s) + 2 omega x S eta') dV,
// and every integral is a combination of the superelement's inertia invariants (see flexible_body.cpp).
// K(omega) = K + K_G(omega) - K_G(omega_ref) when the superelement carries the centrifugal geometric
// stiffness (condense's geometric_stiffening): the prestress of the frame's spin omega (body axes) stiffens
// the modes, the counterpart of the spin softening that h holds (Kane, Ryan & Banerjee, J. Guidance 10(2),
// 1987). "linear" coupling drops the quadratic invariants S_kl everywhere except in the modal mass
// (Adams/Flex' "partial coupling"): the body's inertia and the rotational coupling then follow eta to first
// order only.
#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "common/input.hpp"
#include "solve/body.hpp"

namespace nvh::solve {

/// A superelement as a flexible body uses it: the selected elastic coordinates (the rigid-body content of
/// raw Craig-Bampton / Guyan bases already removed) and the inertia invariants in that basis. SI units.
struct FlexibleData {
  std::filesystem::path file;
  double mass = 0;                                         // kg
  Vec3 first_moment = Vec3::Zero();                        // m c = int rho x dV, kg m (component frame)
  Mat3 second_moment = Mat3::Zero();                       // int rho x x^T dV about the origin, kg m^2
  Eigen::MatrixXd modal_mass, stiffness, damping;          // n x n: int rho S^T S dV, K, D
  Eigen::Matrix<double, 3, Eigen::Dynamic> translational;  // S_bar = int rho S dV (3 x n)
  std::array<Eigen::VectorXd, 9> position;                 // I_tilde_kl = int rho x_k S_l dV, [3 k + l] (n)
  std::array<Eigen::MatrixXd, 9> quadratic;                // S_kl = int rho S_k^T S_l dV, [3 k + l] (n x n)
  Eigen::VectorXd frequency_hz;                            // of the selected coordinates (information)
  int coordinates_in_file = 0;  // elastic coordinates the file offers (the selection may take fewer)
  int static_correction = 0;    // the file's static-correction vectors (SuperelementFile::static_correction)
  int rigid_body_modes = 0;  // the file's rigid-body content (removed or contained): 0 for a supported part
  std::vector<int> mode_numbers;  // the coordinates chosen by number (1-based, `mode_numbers`); empty: by count
  // Centrifugal geometric stiffness (empty, or six n x n matrices for the products omega_a omega_b in the
  // order xx yy zz xy yz zx; per (rad/s)^2) and the spin the stiffness was reduced at (rad/s, component
  // axes): K(omega) = K + sum_p (omega_a omega_b - ref_a ref_b) K_p (docs/hdf5-format.md, /reduced).
  std::vector<Eigen::MatrixXd> geometric;
  Vec3 reference_spin = Vec3::Zero();
  struct Point {
    std::string name;
    Vec3 position = Vec3::Zero();                          // u0, m, component frame
    Eigen::Matrix<double, 3, Eigen::Dynamic> translation;  // Phi_t, m per unit eta (3 x n)
    Eigen::Matrix<double, 3, Eigen::Dynamic> rotation;     // Phi_r, rad per unit eta (3 x n)
  };
  std::vector<Point> points;  // interface points, then observation points
  int size() const { return static_cast<int>(modal_mass.rows()); }
};

/// Load a superelement file and select its lowest `modes` elastic coordinates (all if modes <= 0), or, with
/// `numbers` (1-based, in the file's order of frequency, ascending and distinct), exactly those.
/// Raw Craig-Bampton and Guyan bases (orthonormalized = 0) are first transformed to the elastic modes of
/// (K_r, M_r), dropping the rigid-body modes they contain. Throws nvh::Error naming the file.
FlexibleData load_flexible_data(const std::filesystem::path& file, int modes = 0,
                                const std::vector<int>& numbers = {});

enum class Coupling { kFull, kLinear };

class FlexibleBody final : public Body {
 public:
  /// `point_of_user_marker[k]` is the point (index into data.points) of the k-th marker added after
  /// construction (the scene's [[body.marker]] tables, in order); the points' own markers come first.
  FlexibleBody(std::string name, FlexibleData data, Coupling coupling, InitialState init,
               Eigen::VectorXd eta0, Eigen::VectorXd eta_rate0, std::vector<int> point_of_user_marker = {});

  std::string kind() const override { return "flexible"; }
  /// The frame's states as a rigid body's, then "modal coordinate k" / "modal velocity k" with the frequency.
  std::string state_meaning(int r) const override;
  int position_count() const override { return 7 + n_; }
  int velocity_count() const override { return 6 + n_; }
  Eigen::VectorXd initial_positions() const override;
  Eigen::VectorXd initial_velocities() const override;
  void kinematic_residual(std::span<const double> q, std::span<const double> qdot,
                          std::span<const double> w_eff, std::span<const double> alg, std::span<double> rows,
                          std::span<double> alg_rows) const override;
  Eigen::VectorXd position_rates(std::span<const double> q, std::span<const double> w) const override;
  /// Blockwise from the invariants, without forming M(q); no heap allocation (the workspace below).
  void inertia_residual(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, std::span<double> rows) const override;
  using Body::marker_jacobian;
  using Body::mass_matrix;  // the allocating overloads, hidden otherwise
  void mass_matrix(std::span<const double> q, Eigen::Ref<Eigen::MatrixXd> m) const override;
  MarkerMotion marker_motion(int marker, std::span<const double> q, std::span<const double> w) const override;
  void marker_jacobian(int marker, std::span<const double> q, Eigen::Ref<Mat3X> jv,
                       Eigen::Ref<Mat3X> jw) const override;
  void marker_twist(int marker, std::span<const double> q, std::span<const double> w, Vec3& velocity,
                    Vec3& angular_velocity) const override;
  Vec3 marker_acceleration(int marker, std::span<const double> q, std::span<const double> w,
                           std::span<const double> wdot) const override;
  Vec3 reference_position(std::span<const double> q) const override;
  Mat3 rotation(std::span<const double> q) const override;
  double kinetic_energy(std::span<const double> q, std::span<const double> w) const override;
  /// -m g . r_cm + 1/2 eta^T K eta (J), and the modal damping's power eta'^T D eta' (W).
  double potential_energy(std::span<const double> q, const Vec3& gravity) const override;
  double dissipated_power(std::span<const double> q, std::span<const double> w) const override;

  // Closed-form derivatives for the model's analytic Jacobian (body.hpp; equations in flexible_body.cpp).
  // No heap allocation: fixed-size Eigen types and the workspace below.
  void add_wrench(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                  std::span<double> generalized) const override;
  void marker_sensitivity(int marker, std::span<const double> q, std::span<const double> w,
                          Eigen::Ref<Eigen::MatrixXd> out) const override;
  void add_wrench_derivative(int marker, std::span<const double> q, const Vec3& force, const Vec3& torque,
                             Eigen::Ref<Eigen::MatrixXd> out) const override;
  void kinematic_jacobian(std::span<const double> q, std::span<const double> w_eff,
                          Eigen::Ref<Eigen::MatrixXd> d_q, Eigen::Ref<Eigen::MatrixXd> d_w) const override;
  void inertia_jacobian(std::span<const double> q, std::span<const double> w, std::span<const double> wdot,
                        const Vec3& gravity, Eigen::Ref<Eigen::MatrixXd> d_q,
                        Eigen::Ref<Eigen::MatrixXd> d_w) const override;

  const FlexibleData& data() const { return data_; }
  Coupling coupling() const { return coupling_; }
  int modes() const { return n_; }
  /// Strain energy 1/2 eta^T K eta (J).
  double strain_energy(std::span<const double> q) const;
  /// Centre of mass of the deformed body (global, m): r + A (m c + S_bar eta) / m.
  Vec3 center_of_mass(std::span<const double> q) const;
  /// Linear momentum (kg m/s) and angular momentum about the global origin (kg m^2/s), global axes.
  void momentum(std::span<const double> q, std::span<const double> w, Vec3& linear, Vec3& angular) const;

  static constexpr double kNormalizationRate = 100.0;  // beta, 1/s (as RigidBody)

 private:
  /// The eta-dependent inertia terms (flexible_body.cpp): returns P, whose column 3a+b is P_ab(eta) =
  /// I_tilde_ab + S_ab^T eta (the constant I_tilde columns in linear coupling, ws_p_ with full coupling), and
  /// sets psi = Psi(eta) = int rho s s^T dV. With full coupling ws_s_eta_ then holds S_kl eta. No heap
  /// allocation.
  const Eigen::MatrixXd& inertia_terms(const Eigen::Ref<const Eigen::VectorXd>& eta, Mat3& psi) const;
  int point_of(int marker) const;

  FlexibleData data_;
  Coupling coupling_;
  InitialState init_;
  Eigen::VectorXd eta0_, eta_rate0_;
  int n_;
  int builtin_markers_;
  std::vector<int> user_points_;
  Eigen::MatrixXd position_cols_;  // n x 9: column 3a+b = I_tilde_ab (data_.position, packed)
  // Workspace of the inertial rows and their derivatives (sized in the constructor; the body is not
  // thread-safe, as the model).
  mutable Eigen::MatrixXd ws_s_eta_;   // n x 9: column 3a+b = S_ab eta
  mutable Eigen::MatrixXd ws_s_rate_;  // n x 9: column 3a+b = S_ab eta'
  mutable Eigen::MatrixXd ws_s_acc_;   // n x 9: column 3a+b = S_ab eta''
  mutable Eigen::MatrixXd ws_p_;       // n x 9: column 3a+b = P_ab(eta) = I_tilde_ab + S_ba eta
  mutable Eigen::MatrixXd ws_dpsi_;    // n x 9: column 3k+l = dPsi_kl/deta
  mutable Eigen::Matrix<double, 3, Eigen::Dynamic> ws_3n_;  // 3 x n
  mutable Eigen::VectorXd ws_n_;    // n: D eta' (dissipated_power), K eta (strain_energy)
  mutable Eigen::MatrixXd ws_geo_;  // n x 6: K_p eta (geometric stiffness)
  /// Coefficients omega_a omega_b - ref_a ref_b of the geometric stiffness matrices.
  std::array<double, 6> spin_coefficients(const Vec3& omega) const;
};

/// Build a flexible body from a scene's [[body]] table with type = "flexible" (keys read from `t`; the
/// caller calls t.finish()). `base` is the scene's folder; the superelement file is appended to `inputs`.
std::unique_ptr<Body> make_flexible_body(const input::Table& t, const std::string& name,
                                         const InitialState& init, const std::filesystem::path& base,
                                         std::vector<std::filesystem::path>& inputs);

}  // namespace nvh::solve
