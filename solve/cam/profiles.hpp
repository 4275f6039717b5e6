#pragma once
// The cam profiles behind read_cam_profile (cam_profile.hpp): constructors from SI numbers (for tests and for
// code that builds a cam without an input file) and the readers of each profile's keys.
//
// The readers mark the keys they read as known and do not call finish(): the table is the element's (or the
// component's), whose reader asks for its own keys (markers, type, ...) and then calls finish() once, so that
// unknown keys are reported against all accepted keys (the convention of solve/bearing/bearing_reader.hpp).
// Keys, units and defaults: docs/valvetrain.md, section 1.
#include <memory>
#include <string>
#include <vector>

#include "common/input.hpp"
#include "solve/cam/cam_profile.hpp"

namespace nvh::solve::cam {

/// `x` with `precision` significant digits, for error messages (cam_profile.cpp).
std::string format_number(double x, int precision = 6);
/// The angle in (-pi, pi] equal to `a` modulo 2 pi.
double wrap_pi(double a);
/// The angle in [0, 2 pi) equal to `a` modulo 2 pi.
double wrap_2pi(double a);

// --------------------------------------------------------------------------------------- tangent_cam.cpp
/// The paper's eccentric circular cam (001 eq. 1): a disc of radius Rb + e whose centre is offset by e from
/// the camshaft axis, so that its smallest radius (the base circle) is Rb; peak lift 2 e at cam angle
/// nose_angle (rad). Throws nvh::Error if a radius or e is not > 0.
std::unique_ptr<CamProfile> eccentric_cam(double base_radius, double eccentricity, double roller_radius,
                                          double nose_angle);
/// The tangent cam: base circle Rb, nose circle Rn centred at distance d on the lobe axis, straight flanks
/// tangent to both; peak lift d + Rn - Rb at cam angle nose_angle (rad). Throws nvh::Error (naming the
/// offending quantities) unless Rn < Rb and d > Rb - Rn (the same as d + Rn > Rb: the nose stands out).
std::unique_ptr<CamProfile> tangent_cam(double base_radius, double nose_radius, double lobe_distance,
                                        double roller_radius, double nose_angle);
std::unique_ptr<CamProfile> read_eccentric_cam(const input::Table& t);
std::unique_ptr<CamProfile> read_tangent_cam(const input::Table& t);

// ----------------------------------------------------------------------------------------- table_cam.cpp
/// A tabulated lift: cam angles (rad, strictly increasing, spanning less than 2 pi) and lifts (m),
/// interpolated by a periodic cubic spline (period 2 pi). Throws nvh::Error starting with `where` if the
/// angles do not increase, span 2 pi or more, a lift is negative, or the table is not smooth enough (see
/// table_cam.cpp). A last row at first + 2 pi (within 1e-9 rad) closes the table and must repeat the first
/// lift.
std::unique_ptr<CamProfile> table_cam(std::vector<double> angles, std::vector<double> lifts,
                                      double base_radius, double roller_radius, const std::string& where);
std::unique_ptr<CamProfile> read_table_cam(const input::Table& t, const std::filesystem::path& base,
                                           std::vector<std::filesystem::path>& inputs);

// ------------------------------------------------------------------------------------ polynomial_cam.cpp
/// A symmetric valve-lift event of quintic polynomials (polynomial_cam.cpp). Angles in rad, lifts in m,
/// ramp_velocity in m/rad (< 0: the default 2 ramp_height / ramp_angle).
struct PolynomialEvent {
  double lift = 0;
  double rise_angle = 0;
  double ramp_angle = 0;
  double ramp_height = 0;
  double ramp_velocity = -1;
  double base_radius = 0;
  double roller_radius = 0;
  double nose_angle = 0;
};
/// Throws nvh::Error if the event does not fit in 2 pi, ramp_height >= lift, or the lift is not monotonic on
/// the opening side (a ramp velocity too large or too small for the rise).
std::unique_ptr<CamProfile> polynomial_cam(const PolynomialEvent& event);
std::unique_ptr<CamProfile> read_polynomial_cam(const input::Table& t);

}  // namespace nvh::solve::cam
