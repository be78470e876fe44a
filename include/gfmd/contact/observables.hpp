// Scalar observables of a solved contact (SPEC §5).
#pragma once

#include "gfmd/contact/solver.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd {

struct Observables {
  double relative_contact_area = 0;  // fraction of cells in contact (repulsive pressure > 0)
  double normal_force = 0;           // sum p dA
  double mean_pressure = 0;          // normal_force / (lx ly)
  double max_pressure = 0;
  double mean_gap = 0;  // mean of max(gap, 0) over the cell
  double approach = 0;
  // Friction (zero without friction). Dissipation: F = P_diss / v0 = sum tau . v dA with the
  // slip velocity v = xi e_s + (e_s.grad) u (= mu_c sum p |v| dA where every point slips; stuck
  // points dissipate nothing). Downhill: F = sum |tau| dA + dF, dF = -sum p (e_s.grad h) dA
  // (sum |tau| = mu_c F_z where every point slips).
  // With an upwind slip derivative F also holds the derivative's own dissipation F_num
  // (below): F = F_slip + F_num, F_slip = sum tau.v dA over the slipping points.
  double friction_force = 0;
  double friction_force_slip = 0;
  double friction_force_downhill = 0;
  double downhill_force = 0;
  // dF / F_z: the downhill-slope force per normal force, the quantity the paper's Fig. 2(e)
  // plots (divided by mu_c and the rms gradient; Eq. (8) of its supplement).
  double downhill_friction = 0;
  double friction_coefficient = 0;
  double friction_coefficient_downhill = 0;
  // |F_diss - F_downhill| / F_diss; on a viscoelastic body F_diss + F_h (the body's hysteresis)
  // in place of F_diss in this and the exact balance.
  double energy_balance_error = 0;
  // The force that drives the sliding per normal force, F_drive / F_z: on a viscoelastic body the
  // interface's friction_coefficient plus hysteresis_friction (to the balance's error).
  double total_friction_coefficient = 0;
  // Work of the driving force per v0, xi sum tau.e_s dA + dF: equal to F_diss in steady state
  // (F_downhill replaces tau.e_s by |tau|, a second-order difference in the strains).
  double friction_force_drive = 0;
  double energy_balance_error_exact = 0;  // |F_diss - F_drive| / F_diss
  // With an upwind slip derivative: the dissipation of the difference itself, F_num =
  // sum tau.(v_spectral - v) dA (0 with the spectral derivative), and F_num / F_diss. It
  // stands for the slip the grid does not resolve (at a stick zone's trailing edge).
  double numerical_dissipation = 0;
  double numerical_dissipation_fraction = 0;
  bool friction = false;  // the friction observables were computed (mu_c > 0)
  // A viscoelastic body: the friction force of its hysteresis, F_h = -sum t.(e_s.grad u) dA with
  // t = (tau_x, tau_y, -p) (frictionless: sum p (e_s.grad u_z) dA = -sum p (e_s.grad h) dA where
  // the surfaces touch, the pressure's downhill force), F_h / F_z, and the
  // body's own dissipation per speed from the pressure's spectrum (SolveInfo::
  // hysteresis_dissipation) with its relative difference to F_h: the energy balance.
  bool viscoelastic = false;
  double hysteresis_force = 0, hysteresis_friction = 0, hysteresis_dissipation = 0,
         hysteresis_balance_error = 0;
  double mean_tangential_traction_x = 0, mean_tangential_traction_y = 0;
  // Geometry relative to the indenter's highest point (the Hertz apex), along the
  // sliding direction e_s ("longitudinal") and across it ("transverse"), minimum image.
  double centroid_shift = 0;  // pressure-weighted mean position . e_s
  double centroid_shift_transverse = 0;
  double pressure_max_shift = 0;           // position of max p . e_s
  double contact_extent_longitudinal = 0;  // (max - min) of contact cells . e_s, + dx
  double contact_extent_transverse = 0;
  double max_slip_velocity = 0, min_slip_velocity = 0;  // |v_slip|/v0 over the contact
  // Fraction of all cells in contact and slipping slower than friction.regularization
  // (where the regularised law applies; 0 without regularisation).
  double near_stick_fraction = 0;
  // Exact Coulomb law with stick: fraction of the contact cells that stick (zero slip
  // velocity, traction inside the friction disc).
  double stick_fraction = 0;
  // Plastic saturation (set by the case pipeline where interaction.hardness caps p): the
  // fraction of the cell at the cap, the largest and the mean plastic displacement there.
  bool plastic = false;
  double plastic_area_fraction = 0, max_plastic_displacement = 0, mean_plastic_displacement = 0;
  // Adhesion (interaction.model = "adhesive"): the adhesive pull sum a dA (>= 0), the
  // repulsive force (normal_force + adhesive_force; normal_force is the net force, negative in
  // tension), the fractions of the cell under attraction (contact and cohesive zone) and in the
  // cohesive zone alone (attracted, out of contact), and the most tensile net pressure.
  bool adhesive = false;
  double adhesive_force = 0, repulsive_force = 0, attraction_area_fraction = 0, cohesive_zone_fraction = 0;
  double min_pressure = 0;
  // The cohesive zone's mean width in cells (cells attracted out of contact per cell its outer
  // edge crosses); below about 2 the zone's edge is trapped by the grid.
  double cohesive_zone_cells = 0;
  // Tangential force the body exerts on the indenter, sum tau dA: along e_s and in lab axes;
  // its ratio to the normal force (the traction coefficient of rolling; mu_c where every
  // point slips).
  double tangential_force = 0, tangential_force_x = 0, tangential_force_y = 0;
  double traction_coefficient = 0;
};

// Fields derived from a solved state (all on the grid).
struct DerivedFields {
  RealField slip_longitudinal;  // v_l^rel / v0 - xi: relative longitudinal slip excess ((e_s.grad) u_s)
  RealField slip_transverse;    // transverse slip / v0 ((e_s.grad) u_perp)
  RealField dissipation;        // tau . v_slip / v0 (power density per unit v0; 0 where stuck)
  // Plastic saturation (interaction.hardness): how far the indenter overlaps the undeformed
  // surface beyond the elastic overlap where the pressure is at the cap (0 elsewhere); empty
  // without a cap.
  RealField plastic_displacement;
};
DerivedFields derived_fields(const FFT& fft, const FrictionParams& fric, const ContactFields& f);

// Slip field of the body relative to the indenter in units of v0: v = xi e_s + (e_s.grad)u
// (its sign is that of the indenter's motion seen from the body; |v| is the slip speed).
void slip_velocity(const FFT& fft, const FrictionParams& fric, const RealField& ux, const RealField& uy,
                   RealField& vx, RealField& vy);

// face: the heights whose slope the pressure pushes on in the downhill force, an elastic
// indenter's deformed face (null: topo.h, a rigid indenter's). indenter: an elastic indenter's
// own fields (its displacement in its frame, run_detail::indenter_fields): f's displacement is
// then the pair's, and a viscoelastic body's hysteresis is worked out on the body's own.
Observables compute_observables(const FFT& fft, const Topography& topo, const FrictionParams& fric,
                                const ContactFields& f, const SolveInfo& info,
                                const RealField* face = nullptr, const ContactFields* indenter = nullptr);

}  // namespace gfmd
