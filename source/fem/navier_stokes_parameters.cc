#include <twinflow/fem/navier_stokes.h>

namespace twinflow::fem
{
  void NavierStokesParameters::declare(dealii::ParameterHandler &prm)
  {
    using dealii::Patterns::Integer;
    using dealii::Patterns::Double;
    using dealii::Patterns::Selection;
    prm.declare_entry("Velocity degree", "2", Integer(2, 4),
                      "Polynomial degree k+1 of the Taylor-Hood pair Q_{k+1}/Q_k (pressure degree = velocity degree - 1).");
    prm.declare_entry("Mapping degree", "auto", dealii::Patterns::Anything(),
                      "Degree of the geometry mapping: a number >= 1, or 'auto' (= velocity degree on meshes with curved boundaries, 1 otherwise).");
    prm.declare_entry("Time scheme", "bdf2", Selection("bdf1|bdf2"),
                      "Time discretisation of the projection scheme: backward Euler or (variable-step) BDF2.");
    prm.declare_entry("Viscous term", "auto", Selection("auto|laplacian|symmetric"),
                      "Form of the viscous term: mu grad u : grad v (constant viscosity) or 2 mu eps(u) : eps(v). "
                      "'auto' is laplacian, with one fluid and with two (the forms differ where mu varies, across "
                      "the interface; the symmetric one adds the cross-component blocks to the momentum matrix).");
    prm.declare_entry("Linear solver tolerance", "1e-10", Double(1e-16, 1e-2),
                      "Relative residual reduction of every Krylov solve but the velocity correction's.");
    prm.declare_entry("Velocity correction tolerance", "1e-6", Double(1e-16, 1e-2),
                      "Relative residual of the CG of the variable-density velocity correction (the L2(rho) "
                      "projection of u~ - dt/(a0 rho) grad phi). Its error moves u by this fraction of the "
                      "correction, itself O(dt): 1e-6 changes the dam-break monitors by < 1e-6 relative with "
                      "28 % fewer iterations than 1e-8.");
    prm.declare_entry("AMG rebuild interval", "1", Integer(1, 1000),
                      "Rebuild the velocity preconditioner every n steps (it is reused in between).");
    prm.declare_entry("Pressure AMG interval", "2", Integer(1, 1000),
                      "The variable-density pressure matrix changes every step: its AMG is set up every n "
                      "steps (and after every mesh change) and applied to the later matrices in between, whose "
                      "interface has moved by less than a cell. A solve with a reused AMG that needs more than "
                      "3x the iterations of the last fresh one + 10 is repeated with a fresh AMG. Dam break: "
                      "n = 2 keeps 9.0 -> 9.2 CG iterations and saves a third of the projection, n = 3 takes "
                      "10.4.");
    prm.declare_entry("Pressure projection", "minimum density", Selection("minimum density|variable density"),
                      "Pressure increment of a variable density: -Lap(phi) = -(a0 rho_min/dt) div u (Guermond & "
                      "Salgado 2009, the paper's Eq. 16; mesh-only matrix) or -div(grad(phi)/rho) = -(a0/dt) div u "
                      "(matrix rebuilt every step).");
    prm.declare_entry("Streamline diffusion", "0", Double(0, 10),
                      "c of the streamline-diffusion stabilisation of the convection term, "
                      "c tau_K rho (u*.grad u)(u*.grad v) with tau_K = h_K / (2 |u*|) (c rho h |u| / 2 "
                      "along streamlines; 0: Galerkin). Free-surface scenes need it: the air "
                      "(rho 1.2, mu 1.8e-5) has cell Reynolds numbers of 1e3 and more.");
    prm.declare_entry("Velocity preconditioner", "amg", Selection("amg|ilu|ssor|jacobi"),
                      "Preconditioner of the velocity GMRES: Trilinos ML AMG (Gauss-Seidel smoothing), ILU(0), "
                      "SSOR or Jacobi (the last two cost nothing to set up; enough when the step makes the "
                      "matrix mass-dominated, as in two-phase runs at the CFL limit).");
  }

  void NavierStokesParameters::parse(dealii::ParameterHandler &prm)
  {
    velocity_degree      = prm.get_integer("Velocity degree");
    scheme               = prm.get("Time scheme") == "bdf1" ? TimeScheme::bdf1 : TimeScheme::bdf2;
    const std::string vf = prm.get("Viscous term");
    viscous_form         = vf == "symmetric" ? ViscousForm::symmetric : ViscousForm::laplacian;
    linear_tolerance     = prm.get_double("Linear solver tolerance");
    correction_tolerance = prm.get_double("Velocity correction tolerance");
    amg_rebuild_interval = prm.get_integer("AMG rebuild interval");
    pressure_amg_interval = prm.get_integer("Pressure AMG interval");
    velocity_preconditioner = prm.get("Velocity preconditioner");
    streamline_diffusion    = prm.get_double("Streamline diffusion");
    variable_projection     = prm.get("Pressure projection") == "variable density";
    const std::string md = prm.get("Mapping degree");
    if (md == "auto")
      mapping_degree = 0; // resolved by the simulation from the geometry
    else
    {
      int v = 0;
      try { v = std::stoi(md); } catch (...) { v = 0; }
      AssertThrow(v >= 1 && v <= 6,
                  dealii::ExcMessage("FEM/Navier-Stokes/Mapping degree = '" + md +
                                     "': allowed values are 'auto' or an integer in [1, 6]."));
      mapping_degree = v;
    }
  }
} // namespace twinflow::fem
