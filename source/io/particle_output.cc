/**
 * @file particle_output.cc
 * Implementation of ParticleOutput (instantiated for dim = 2, 3).
 */
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/particle_output.h>

#include <deal.II/numerics/data_component_interpretation.h>

#include <fstream>

namespace twinflow::io
{
  template <int dim>
  ParticleOutput<dim>::ParticleOutput()
  {
    vtk_flags.compression_level = dealii::DataOutBase::VtkFlags::best_speed;
    vtk_flags.print_date_and_time = false;
  }

  template <int dim>
  std::size_t
  ParticleOutput<dim>::n_particles() const
  {
    return points.size();
  }

  template <int dim>
  void
  ParticleOutput<dim>::clear_fields()
  {
    fields.clear();
  }

  template <int dim>
  void
  ParticleOutput<dim>::clear()
  {
    points.clear();
    fields.clear();
  }

  template <int dim>
  void
  ParticleOutput<dim>::set_flags(const dealii::DataOutBase::VtkFlags &flags)
  {
    vtk_flags = flags;
  }

  template <int dim>
  void
  ParticleOutput<dim>::set_time(const double time, const unsigned int cycle)
  {
    vtk_flags.time  = time;
    vtk_flags.cycle = cycle;
  }

  template <int dim>
  void
  ParticleOutput<dim>::add_field(const std::string & name,
                                 const unsigned int  n_components,
                                 std::vector<float> &&values)
  {
    if (name.empty() || name.find_first_of("\"<>&") != std::string::npos)
      throw std::invalid_argument("ParticleOutput: invalid field name '" + name + "'");
    for (const auto &f : fields)
      if (f.name == name)
        throw std::invalid_argument("ParticleOutput: field '" + name + "' added twice");
    if (values.size() % n_components != 0)
      throw std::invalid_argument("ParticleOutput: vector field '" + name +
                                  "' size is not a multiple of dim");
    fields.push_back(Field{name, n_components, std::move(values)});
  }

  template <int dim>
  std::vector<dealii::DataOutBase::Patch<0, dim>>
  ParticleOutput<dim>::build_patches() const
  {
    unsigned int n_rows = 0;
    for (const auto &f : fields)
      {
        if (f.values.size() != points.size() * f.n_components)
          throw std::invalid_argument("ParticleOutput: field '" + f.name + "' has " +
                                      std::to_string(f.values.size() / f.n_components) +
                                      " entries for " + std::to_string(points.size()) +
                                      " particles");
        n_rows += f.n_components;
      }

    std::vector<dealii::DataOutBase::Patch<0, dim>> patches(points.size());
    for (std::size_t p = 0; p < points.size(); ++p)
      {
        auto &patch = patches[p];
        for (int d = 0; d < dim; ++d)
          patch.vertices[0][d] = points[p][d];
        patch.patch_index = static_cast<unsigned int>(p);
        patch.data.reinit(n_rows, 1);
        unsigned int row = 0;
        for (const auto &f : fields)
          for (unsigned int c = 0; c < f.n_components; ++c, ++row)
            patch.data(row, 0) = f.values[p * f.n_components + c];
      }
    return patches;
  }

  template <int dim>
  std::vector<std::string>
  ParticleOutput<dim>::data_names() const
  {
    std::vector<std::string> names;
    for (const auto &f : fields)
      for (unsigned int c = 0; c < f.n_components; ++c)
        names.push_back(f.name);
    return names;
  }

  template <int dim>
  std::vector<std::tuple<unsigned int,
                         unsigned int,
                         std::string,
                         dealii::DataComponentInterpretation::DataComponentInterpretation>>
  ParticleOutput<dim>::nonscalar_data_ranges() const
  {
    std::vector<std::tuple<unsigned int,
                           unsigned int,
                           std::string,
                           dealii::DataComponentInterpretation::DataComponentInterpretation>>
                 ranges;
    unsigned int first = 0;
    for (const auto &f : fields)
      {
        if (f.n_components > 1)
          ranges.emplace_back(first,
                              first + f.n_components - 1,
                              f.name,
                              dealii::DataComponentInterpretation::component_is_part_of_vector);
        first += f.n_components;
      }
    return ranges;
  }

  template <int dim>
  void
  ParticleOutput<dim>::write_vtu(std::ostream &out) const
  {
    dealii::DataOutBase::write_vtu(build_patches(), data_names(), nonscalar_data_ranges(),
                                   vtk_flags, out);
  }

  template <int dim>
  void
  ParticleOutput<dim>::write_vtu(const std::string &filename) const
  {
    ensure_parent_directory(filename);
    std::ofstream out(filename, std::ios::out | std::ios::trunc | std::ios::binary);
    if (!out)
      throw std::runtime_error("ParticleOutput: cannot open '" + filename + "' for writing");
    write_vtu(out);
    out.flush();
    if (!out)
      throw std::runtime_error("ParticleOutput: write to '" + filename + "' failed");
  }

  template class ParticleOutput<2>;
  template class ParticleOutput<3>;
} // namespace twinflow::io
