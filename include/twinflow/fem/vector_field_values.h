#pragma once
/**
 * @file vector_field_values.h
 * Values and divergences of a velocity of FESystem(FE_Q(k), dim) at the points of a scalar
 * FEValues of its base element FE_Q(k).
 *
 * Every component of the Taylor–Hood velocity uses the same scalar shape functions. An FEValues
 * of the FESystem computes them and then copies them into dim × n_scalar system functions on
 * every reinit, and FEValuesViews look up the component of every system function at every
 * point. The cell loops that only read the velocity, and the momentum assembly (built from the
 * scalar functions), reinit one scalar FEValues and evaluate through the component table here.
 */
#include <deal.II/base/exceptions.h>
#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>

#include <vector>

namespace twinflow::fem
{
  template <int dim>
  class VectorFieldValues
  {
  public:
    /// @p system: FESystem(FE_Q(k), dim) (one base element of multiplicity dim).
    explicit VectorFieldValues(const dealii::FiniteElement<dim> &system)
    {
      AssertThrow(system.n_base_elements() == 1 && system.element_multiplicity(0) == dim,
                  dealii::ExcMessage("VectorFieldValues: the element must be FESystem(FE_Q(k), dim)."));
      n_scalar = system.base_element(0).n_dofs_per_cell();
      index.resize(dim * n_scalar);
      for (unsigned int c = 0; c < dim; ++c)
        for (unsigned int a = 0; a < n_scalar; ++a)
          index[c * n_scalar + a] = system.component_to_system_index(c, a);
    }

    /// u(x_q) and, if @p divergence is given, ∇·u(x_q), from the cell's DoF values @p local
    /// (system order), at the points of @p scalar (reinit on the same cell).
    void evaluate(const dealii::FEValues<dim> &scalar, const std::vector<double> &local,
                  std::vector<dealii::Tensor<1, dim>> &value, std::vector<double> *divergence = nullptr) const
    {
      const unsigned int nq = scalar.n_quadrature_points;
      value.assign(nq, dealii::Tensor<1, dim>());
      for (unsigned int q = 0; q < nq; ++q)
        for (unsigned int a = 0; a < n_scalar; ++a)
        {
          const double s = scalar.shape_value(a, q);
          for (unsigned int c = 0; c < dim; ++c)
            value[q][c] += s * local[index[c * n_scalar + a]];
        }
      if (divergence)
        this->divergence(scalar, local, *divergence);
    }

    /// u(x_q) from the values of the scalar shape functions at the points, @p shape(a, q) (a
    /// table of the reference cell: FE_Q's values do not depend on the cell).
    void evaluate(const dealii::FullMatrix<double> &shape, const std::vector<double> &local,
                  std::vector<dealii::Tensor<1, dim>> &value) const
    {
      AssertDimension(shape.m(), n_scalar);
      value.assign(shape.n(), dealii::Tensor<1, dim>());
      for (unsigned int q = 0; q < shape.n(); ++q)
        for (unsigned int a = 0; a < n_scalar; ++a)
          for (unsigned int c = 0; c < dim; ++c)
            value[q][c] += shape(a, q) * local[index[c * n_scalar + a]];
    }

    /// ∇·u(x_q) only.
    void divergence(const dealii::FEValues<dim> &scalar, const std::vector<double> &local, std::vector<double> &out) const
    {
      const unsigned int nq = scalar.n_quadrature_points;
      out.assign(nq, 0.0);
      for (unsigned int q = 0; q < nq; ++q)
        for (unsigned int a = 0; a < n_scalar; ++a)
        {
          const dealii::Tensor<1, dim> &g = scalar.shape_grad(a, q);
          for (unsigned int c = 0; c < dim; ++c)
            out[q] += g[c] * local[index[c * n_scalar + a]];
        }
    }

  private:
    unsigned int              n_scalar = 0;
    std::vector<unsigned int> index; ///< system index of (component c, scalar function a)
  };
} // namespace twinflow::fem
