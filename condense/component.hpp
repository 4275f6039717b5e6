#pragma once
// A component as the user describes it in COMPONENT.toml, after validation: plain data, SI units
// (m, kg, s, N, Pa). The file format is documented in docs/component-format.md.
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/error.hpp"

namespace nvh::condense {

using Vec3 = std::array<double, 3>;

/// Isotropic linear-elastic material.
struct Material {
  std::string name;
  double E = 0.0;    ///< Young's modulus, Pa
  double nu = 0.0;   ///< Poisson's ratio, -1 < nu < 0.5
  double rho = 0.0;  ///< density, kg/m^3
  double shear_modulus() const { return E / (2.0 * (1.0 + nu)); }
};

/// Cross-section properties of a beam segment, about its centroid and principal axes.
struct BeamSection {
  double A = 0.0;   ///< area, m^2
  double Iy = 0.0;  ///< second moment about the local y axis, m^4 (bending in the x-z plane)
  double Iz = 0.0;  ///< second moment about the local z axis, m^4 (bending in the x-y plane)
  double J = 0.0;   ///< torsion constant (St. Venant), m^4
  /// Timoshenko shear factor kappa (same for both directions); empty: no shear deformation
  /// (Euler-Bernoulli stiffness; the rotary inertia is still kept unless rotary_inertia = false).
  std::optional<double> shear_factor;
  /// Rotary inertia of bending (default true: the Rayleigh/Timoshenko mass). false gives the classical
  /// Euler-Bernoulli mass, for comparison with its textbook frequencies.
  bool rotary_inertia = true;
  /// Direction that fixes the local y axis (projected normal to the segment); empty: automatic.
  std::optional<Vec3> y_axis;
  std::string material;  ///< material name; empty: the beam's material
  SourceLocation where;  ///< for messages
};

struct PointMass {
  Vec3 at{};
  double m = 0.0;  ///< kg
  Vec3 J{};        ///< principal moments of inertia about the point, in component axes, kg m^2
  SourceLocation where;
  std::string path;  ///< key path of the entry, e.g. "beam.mass[2]"
};

/// A rigid offset from a station of the beam (master) to a point (slave node with its own 6 DOF tied).
struct RigidLink {
  Vec3 from{};
  Vec3 to{};
  SourceLocation where;
  std::string path;  ///< e.g. "beam.rigid[1]"
};

/// The mesh nodes on a cylinder band (a bearing bore, a liner): nodes whose distance r from the axis
/// (through `point`, along `axis`) lies in [r_min, r_max] and whose axial coordinate
/// s = (x - point) . axis / |axis| lies in [s_min, s_max]. All in m.
struct CylinderSelector {
  Vec3 point{};
  Vec3 axis{};  ///< direction, not necessarily of unit length
  double r_min = 0.0, r_max = 0.0;
  double s_min = -1e300, s_max = 1e300;  ///< unbounded unless `length` is given
};

/// Supported degrees of freedom at a point, or at every node inside a box: mask over x y z rx ry rz.
struct Support {
  Vec3 at{};
  std::optional<std::array<double, 6>> box;  ///< xmin ymin zmin xmax ymax zmax (m); replaces `at`
  std::string surface;                       ///< volume models: a node set (upper case); or ...
  std::optional<CylinderSelector> cylinder;  ///< ... the nodes on a cylinder band
  std::array<bool, 6> dofs{};
  SourceLocation where;
  std::string path;  ///< e.g. "fix[1]"
};

/// A named point of the model: interface (kept as physical 6-DOF node) or observation point.
struct NamedPoint {
  std::string name;
  Vec3 at{};
  SourceLocation where;
  std::string path;  ///< e.g. "interface[3]"
  // Volume interfaces only: the coupling of the point to a surface of the mesh.
  std::string surface;                       ///< node set (*NSET) of the mesh, upper case; or ...
  std::optional<std::array<double, 6>> box;  ///< ... the nodes inside a box, m; or ...
  std::optional<CylinderSelector> cylinder;  ///< ... the nodes on a cylinder band (a bore)
  bool distributing = false;                 ///< RBE3 (weighted average, no stiffness) instead of RBE2
  double max_distance = 0.0;      ///< m; 0: the point may lie at most the surface's size from its surface
  SourceLocation selector_where;  ///< of its surface, box or cylinder key, for messages
};

enum class ReductionMethod { kModal, kCraigBampton, kGuyan };

struct ReductionSettings {
  ReductionMethod method = ReductionMethod::kCraigBampton;
  double fmax_hz = 0.0;  ///< keep modes up to fmax (> 0) ...
  int modes = 0;         ///< ... or this many modes (> 0); exactly one of the two is set
  bool orthonormalize = true;
  /// Modal only: add the inertia-relief residual (attachment) modes of the interface DOF, so a static
  /// load at the interfaces is represented exactly (reduction.cpp, residual_attachment_modes).
  bool residual_modes = false;
  bool residual_modes_given = false;  ///< the file said; otherwise default_residual_modes() decides
  /// Craig-Bampton of a volume only: static residual vectors for unit forces along the surface normal at
  /// these observation points (names; "prefix*" takes every point whose name starts with prefix), so that a
  /// static load there - a film's pressure on a skirt - is represented exactly (reduction.cpp,
  /// load_residual_vectors; Nastran's RESVEC). Empty: none.
  std::vector<std::string> residual_vectors;
  /// m: each point's unit load spread evenly over the surface nodes within this distance of it (each along
  /// its own normal), a patch of pressure rather than a point force, whose local dent a solid's mesh would
  /// resolve and a smooth pressure does not make. 0: the point's node alone.
  double residual_patch = 0.0;
  /// Keep the directions of the load points' residual flexibility down to this fraction of its largest.
  double residual_tolerance = 1e-4;
  SourceLocation residual_where;  ///< of residual_vectors, for messages
  /// Write the centrifugal geometric stiffness per product of the spin's components
  /// (geometric_stiffness.hpp), so that solve stiffens the body at its own spin.
  bool geometric_stiffening = false;
  /// Reduce at this spin (rad/s, component axes, about the component origin): the modes of
  /// K + K_G(spin). Zero: at rest. Implies geometric_stiffening.
  Vec3 spin{};
  double damping_ratio = 0.0;  ///< modal damping ratio zeta of the retained modes
  /// The band the results must cover, Hz (0: not given). Given, condense estimates the error of the
  /// reduced model's receptance at every interface in (0, band] (frf_error.hpp); given without fmax and
  /// modes, it also chooses the cut-off: the lowest that brings the estimate below frf_tolerance.
  double band_hz = 0.0;
  double frf_tolerance = 0.01;  ///< relative error of the interface receptance the cut-off must reach
  int error_samples = 16;       ///< frequencies sampled in the band (at least one between resonances)
  SourceLocation band_where;    ///< of band, for messages
  SourceLocation where;         ///< of fmax or modes (or of the table), for messages
  std::string where_key = "reduction.fmax";  ///< the key (or command-line option) that set the count
};

/// A modal reduction whose cut-off is chosen from the band adds residual modes unless the file says
/// otherwise: without them the static response at the interfaces keeps the truncation error.
inline void default_residual_modes(ReductionSettings& r) {
  if (r.residual_modes_given) return;
  r.residual_modes =
      r.band_hz > 0.0 && r.fmax_hz <= 0.0 && r.modes <= 0 && r.method == ReductionMethod::kModal;
}

struct BeamGeometry {
  std::vector<Vec3> points;  ///< stations along the beam's axis (a polyline), m
  int elements_per_segment = 8;
  std::string material;
  /// Section of each segment (segment s joins points[s] and points[s+1]; 0-based here).
  std::vector<BeamSection> segment_sections;
  std::vector<PointMass> masses;
  std::vector<RigidLink> rigid_links;
  SourceLocation where;
};

/// A part of a volume mesh with its own material: the elements of a 3D physical group (gmsh) or of an
/// element set (*ELSET of an .inp).
struct MaterialRegion {
  std::string group;     ///< element set name, upper case
  std::string material;  ///< a name under [material]
  SourceLocation where;  ///< of its group key, for messages
  std::string path;      ///< key path of the entry, e.g. "volume.region[2]"
};

/// A 3D solid component from a mesh made elsewhere (Abaqus/CalculiX .inp: C3D4, C3D10, C3D8, C3D20).
/// How distributing (RBE3) couplings enter the model (fe_model.hpp): six surface DOF per coupling made
/// dependent (elimination: a dense block of the factor per surface), or linear constraints C u = 0 kept
/// beside a sparse K (multiplier: Craig-Bampton and Guyan whose interior the other interfaces and supports
/// restrain, without band, preload or geometric stiffening). kAuto: the multiplier form where it applies.
enum class DistributingForm { kAuto, kElimination, kMultiplier };

struct VolumeGeometry {
  std::filesystem::path mesh;           ///< resolved against the component file's directory
  std::string material;                 ///< the default: every element in no region
  std::vector<MaterialRegion> regions;  ///< [[volume.region]]: element sets with their own material
  bool mass_like_calculix = false;      ///< integrate the mass with the stiffness rule, as CalculiX does
  int order = 2;                        ///< geometry meshed by gmsh: 1 (C3D4) or 2 (C3D10)
  double size = 0.0;                    ///< geometry meshed by gmsh: element size, m (0: the geometry's own)
  /// ... or the size from the frequency range: at most 1/n of the shear wavelength at reduction.fmax.
  double elements_per_wavelength = 0.0;
  DistributingForm rbe3_form = DistributingForm::kAuto;  ///< [volume] rbe3_form
  SourceLocation where;
};

/// A static preload at a named point (an interface or an observation point), for the prestress it causes
/// (geometric_stiffness.hpp): a force (N) and a moment (N m), component axes. The moment needs the point's
/// rotations (a beam node or a volume's interface; a volume's observation point has translations only).
struct Preload {
  std::string point;
  Vec3 force{};
  Vec3 moment{};
  SourceLocation where;
  std::string path;  ///< e.g. "preload[1]"
};

struct Component {
  std::string name;
  std::string kind;  ///< "beam" | "volume"
  std::filesystem::path file;
  std::map<std::string, Material> materials;
  BeamGeometry beam;
  VolumeGeometry volume;
  std::vector<Support> supports;
  std::vector<NamedPoint> interfaces;
  std::vector<NamedPoint> observers;
  std::vector<Preload> preloads;  ///< [[preload]]: the stiffness is that of the preloaded part
  ReductionSettings reduction;
  bool export_surface = false;    ///< [surface] export: write the outer surface and its mode shapes
  double point_tolerance = 1e-6;  ///< m: how far a named point may lie from a node of the model
};

std::string to_string(ReductionMethod method);

}  // namespace nvh::condense
