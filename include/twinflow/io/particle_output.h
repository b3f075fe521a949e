#pragma once
/**
 * @file particle_output.h
 * Particle sets (SPH particles, tracers) written as ParaView `.vtu` files
 * through deal.II's DataOutBase: one zero-dimensional patch (a VTK vertex)
 * per particle, scalar and vector point data per particle.
 *
 * @code
 * ParticleOutput<2> output;
 * output.set_positions(positions);          // std::vector<std::array<double, 2>>
 * output.add_scalar("density", rho);        // std::vector<double> or <float>
 * output.add_vector("velocity", velocity);  // std::vector<std::array<double, 2>>
 * output.write_vtu("out/sph/particles_00042.vtu");
 * series.add(t, "particles_00042.vtu");     // PvdSeries
 * @endcode
 *
 * Field values are stored in single precision (deal.II's Patch::data is a
 * Table<2, float>), and deal.II's VTU writer also stores the point
 * coordinates as Float32 — ample for visualisation, not for restarts.
 * 2D vector fields are padded with a zero z component by the VTU writer, so
 * ParaView shows them as vectors (glyphs, "Magnitude" colouring).
 * The output is not MPI-aware: every calling process writes the particles it
 * was given to the file name it was given. With distributed particles use one
 * file name per rank (grouped by dealii::DataOutBase::write_pvtu_record());
 * with replicated particles call it on one rank only (see is_root_process()).
 */
#include <deal.II/base/data_out_base.h>

#include <array>
#include <cstddef>
#include <ostream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace twinflow::io
{
  /// Collects particle positions and per-particle fields and writes them as VTU.
  template <int dim>
  class ParticleOutput
  {
    static_assert(dim == 2 || dim == 3, "ParticleOutput is instantiated for dim = 2, 3");

  public:
    /// Compressed binary VTU (zlib best_speed), no date/time comment.
    ParticleOutput();

    /// Positions, one array per particle (replaces earlier positions).
    template <typename Number>
    void
    set_positions(const std::vector<std::array<Number, dim>> &positions)
    {
      points.assign(positions.size(), {});
      for (std::size_t p = 0; p < positions.size(); ++p)
        for (int d = 0; d < dim; ++d)
          points[p][d] = static_cast<double>(positions[p][d]);
    }

    /// Positions as a flat array x0 y0 (z0) x1 y1 (z1) ...; size must be a multiple of dim.
    template <typename Number>
    void
    set_positions_flat(const std::vector<Number> &xyz)
    {
      if (xyz.size() % dim != 0)
        throw std::invalid_argument("ParticleOutput: flat position array size not a multiple of dim");
      points.assign(xyz.size() / dim, {});
      for (std::size_t i = 0; i < xyz.size(); ++i)
        points[i / dim][i % dim] = static_cast<double>(xyz[i]);
    }

    /// A scalar field, one value per particle.
    template <typename Number>
    void
    add_scalar(const std::string &name, const std::vector<Number> &values)
    {
      add_field(name, 1, std::vector<float>(values.begin(), values.end()));
    }

    /// A vector field, one dim-array per particle.
    template <typename Number>
    void
    add_vector(const std::string &name, const std::vector<std::array<Number, dim>> &values)
    {
      std::vector<float> flat(values.size() * dim);
      for (std::size_t p = 0; p < values.size(); ++p)
        for (int d = 0; d < dim; ++d)
          flat[p * dim + d] = static_cast<float>(values[p][d]);
      add_field(name, dim, std::move(flat));
    }

    /// A vector field as flat array v0x v0y (v0z) v1x ...
    template <typename Number>
    void
    add_vector_flat(const std::string &name, const std::vector<Number> &values)
    {
      add_field(name, dim, std::vector<float>(values.begin(), values.end()));
    }

    /// Number of particles (from the positions).
    std::size_t
    n_particles() const;

    /// Remove the fields, keep the positions.
    void
    clear_fields();

    /// Remove positions and fields.
    void
    clear();

    /// Replace the VTU flags (compression, time and cycle written into the file, ...).
    void
    set_flags(const dealii::DataOutBase::VtkFlags &flags);

    /// Record simulated time and step in the file (VtkFlags::time / cycle; cycle 0 is not written).
    void
    set_time(double time, unsigned int cycle = 0);

    /**
     * One Patch<0, dim> per particle: vertices[0] = position, data an
     * (n_data_components × 1) table in the order of data_names().
     * Throws std::invalid_argument if a field size does not match n_particles().
     */
    std::vector<dealii::DataOutBase::Patch<0, dim>>
    build_patches() const;

    /// One name per data component (vector fields: the name repeated dim times).
    std::vector<std::string>
    data_names() const;

    /// The ranges of data components that form vectors (for DataOutBase::write_vtu).
    std::vector<std::tuple<unsigned int,
                           unsigned int,
                           std::string,
                           dealii::DataComponentInterpretation::DataComponentInterpretation>>
    nonscalar_data_ranges() const;

    /// Write the VTU document to @p out.
    void
    write_vtu(std::ostream &out) const;

    /// Write the VTU file @p filename (creating its directory); throws std::runtime_error on I/O errors.
    void
    write_vtu(const std::string &filename) const;

  private:
    struct Field
    {
      std::string        name;
      unsigned int       n_components;
      std::vector<float> values; ///< particle-major: values[p * n_components + c]
    };

    void
    add_field(const std::string &name, unsigned int n_components, std::vector<float> &&values);

    std::vector<std::array<double, dim>> points;
    std::vector<Field>                   fields;
    dealii::DataOutBase::VtkFlags        vtk_flags;
  };
} // namespace twinflow::io
