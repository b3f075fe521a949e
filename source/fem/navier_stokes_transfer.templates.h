// NavierStokes<dim>: the mesh-change and checkpoint parts of the FieldPhysics life cycle.
#pragma once
#include <twinflow/fem/navier_stokes.h>

#include <deal.II/dofs/dof_tools.h>

#include <istream>
#include <ostream>

namespace twinflow::fem
{
  using namespace dealii;

  template <int dim>
  void NavierStokes<dim>::make_mesh_constraints(const DoFHandler<dim> &dofs, const IndexSet &relevant,
                                                AffineConstraints<double> &c) const
  {
    c.clear();
    c.reinit(relevant);
    DoFTools::make_hanging_node_constraints(dofs, c);
    for (const auto &pp : periodic)
      DoFTools::make_periodicity_constraints(dofs, pp.b1, pp.b2, pp.direction, c);
    c.close();
  }

  template <int dim>
  void NavierStokes<dim>::prepare_transfer(const bool serialization)
  {
    velocity_transfer = std::make_unique<Transfer>(velocity_dofs);
    pressure_transfer = std::make_unique<Transfer>(pressure_dofs);
    // The input vectors must stay alive until finish_transfer: they are members (ghosted).
    const std::vector<const TrilinosWrappers::MPI::Vector *> u{&u_n, &u_nm1}, p{&p_n, &phi_n, &phi_nm1};
    if (serialization)
    {
      velocity_transfer->prepare_for_serialization(u);
      pressure_transfer->prepare_for_serialization(p);
    }
    else
    {
      velocity_transfer->prepare_for_coarsening_and_refinement(u);
      pressure_transfer->prepare_for_coarsening_and_refinement(p);
    }
  }

  template <int dim>
  void NavierStokes<dim>::finish_transfer(const bool serialization)
  {
    if (serialization)
    {
      // Restart: the vectors come from the file Triangulation::load() read.
      velocity_transfer = std::make_unique<Transfer>(velocity_dofs);
      pressure_transfer = std::make_unique<Transfer>(pressure_dofs);
    }
    AssertThrow(velocity_transfer && pressure_transfer,
                ExcMessage("NavierStokes::finish_transfer without prepare_transfer"));
    // Interpolation writes owned vectors; the hanging-node constraints of the new mesh then
    // make them conforming, and the ghosted members receive them.
    auto finish = [&](Transfer &transfer, const DoFHandler<dim> &dofs, const IndexSet &owned,
                      const IndexSet &relevant, const std::vector<TrilinosWrappers::MPI::Vector *> &targets) {
      std::vector<TrilinosWrappers::MPI::Vector>   fresh(targets.size(), TrilinosWrappers::MPI::Vector(owned, comm));
      std::vector<TrilinosWrappers::MPI::Vector *> out;
      for (auto &v : fresh)
        out.push_back(&v);
      if (serialization)
        transfer.deserialize(out);
      else
        transfer.interpolate(out);
      AffineConstraints<double> constraints;
      make_mesh_constraints(dofs, relevant, constraints);
      for (std::size_t k = 0; k < targets.size(); ++k)
      {
        constraints.distribute(fresh[k]);
        *targets[k] = fresh[k];
      }
    };
    finish(*velocity_transfer, velocity_dofs, velocity_owned, velocity_relevant, {&u_n, &u_nm1});
    finish(*pressure_transfer, pressure_dofs, pressure_owned, pressure_relevant, {&p_n, &phi_n, &phi_nm1});
    velocity_transfer.reset();
    pressure_transfer.reset();
    ++state_counter;
  }

  template <int dim>
  void NavierStokes<dim>::save_state(std::ostream &out) const
  {
    out.precision(17);
    out << "navier-stokes " << current_time << ' ' << dt_last << ' ' << dt_before_last << ' ' << step_number << ' '
        << have_history << '\n';
  }

  template <int dim>
  void NavierStokes<dim>::load_state(std::istream &in)
  {
    std::string tag;
    in >> tag >> current_time >> dt_last >> dt_before_last >> step_number >> have_history;
    AssertThrow(in && tag == "navier-stokes",
                ExcMessage("checkpoint metadata: the navier-stokes line is missing or malformed"));
    make_velocity_constraints(current_time);
    rebuild_velocity_preconditioner = true;
    ++state_counter;
  }
} // namespace twinflow::fem
