#pragma once
/**
 * @file mesh_adaptation.h
 * Band refinement around interfaces (Section 3.3.1: the IBM "requires a fine mesh near the
 * solid level set"; the free surface φ = 0 registers the same way).
 *
 * A cell is *in the band* of an interface when the interface comes closer than
 * c · h_max to it (|φ(x_K)| − r_K < c · h_max, x_K its centre, r_K its circumradius,
 * h_max the cell size at the maximum level). Marking: band cells refine up to the maximum
 * level; the others coarsen down to the minimum level; optionally the cells whose Kelly
 * indicator of the velocity exceeds a fraction of the largest one refine on top (a
 * threshold relative to the global maximum marks the same cells on any number of ranks). p4est enforces the 2:1 balance;
 * hanging-node constraints are built by every physics in setup_dofs().
 */
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace twinflow::fem
{
  /// Parameters of subsection "FEM/Mesh adaptation".
  struct MeshAdaptationParameters
  {
    unsigned int minimum_level  = 0;   ///< coarsest level away from every interface
    unsigned int maximum_level  = 0;   ///< level in the interface bands; 0 = no adaptation
    double       band_width     = 4;   ///< c: half-width of the band in cells of the maximum level
    unsigned int interval       = 10;  ///< steps between adaptation checks
    double       move_fraction  = 0.25;///< re-adapt when an interface moved more than this × band
    double       kelly_threshold = 0;  ///< refine where η_K > this × max η (Kelly; 0: off)

    bool enabled() const { return maximum_level > 0; }

    static void declare(dealii::ParameterHandler &prm);
    void        parse(dealii::ParameterHandler &prm);
  };

  /// An interface the mesh follows: the zero level of a signed distance.
  template <int dim>
  class AdaptationInterface
  {
  public:
    virtual ~AdaptationInterface() = default;
    virtual std::string name() const = 0;
    /// Signed distance to the interface (only |φ| matters here).
    virtual double distance(const dealii::Point<dim> &x) const = 0;
    /// Signed distance at the centre of a locally owned @p cell (fields that live on the mesh
    /// answer it from their DoFs; the default evaluates distance() at the centre).
    virtual double cell_distance(const typename dealii::Triangulation<dim>::active_cell_iterator &cell) const
    {
      return distance(cell->center());
    }
    /// Largest displacement of the interface since the last call of mark_adapted() [m].
    virtual double displacement_since_adaptation() const { return 0; }
    /// The mesh was adapted to the current position.
    virtual void mark_adapted() {}
  };

  template <int dim>
  class MeshAdaptation
  {
  public:
    MeshAdaptation(dealii::parallel::distributed::Triangulation<dim> &tria,
                   const MeshAdaptationParameters                    &parameters);

    /// Cells of the mesh follow @p interface from now on (it must outlive this object).
    void register_interface(AdaptationInterface<dim> &interface) { tracked.push_back(&interface); }
    const std::vector<AdaptationInterface<dim> *> &interfaces() const { return tracked; }

    /// Cell size at the maximum level (the smallest cell of the adapted mesh).
    double finest_cell_size() const;
    /// Half-width of the bands [m].
    double band_half_width() const { return prm.band_width * finest_cell_size(); }

    /// Whether the cell lies in the band of any registered interface.
    bool in_band(const typename dealii::Triangulation<dim>::active_cell_iterator &cell) const;

    /// Sets refine/coarsen flags (band, levels, optional Kelly @p indicator over the active
    /// cells, may be null) and returns whether the mesh would change on any rank.
    bool mark(const dealii::Vector<float> *indicator);

    /// After step @p step: is a check due, and did an interface move enough (or is Kelly on)?
    bool due(unsigned int step) const;

    /// Interfaces take their current position as the adapted one.
    void mark_adapted();

    const MeshAdaptationParameters &parameters() const { return prm; }

  private:
    dealii::parallel::distributed::Triangulation<dim> &tria;
    MeshAdaptationParameters                           prm;
    std::vector<AdaptationInterface<dim> *>            tracked;
    double                                             coarse_cell_size = 0;
  };
} // namespace twinflow::fem
