#include <twinflow/core/errors.h>
#include <twinflow/sph/open_boundary.h>

#include <vector>

namespace twinflow::sph
{
  namespace
  {
    const char *face_names[6] = {"left", "right", "bottom", "top", "front", "back"};

    /// Keeps the entries of @p v where @p keep is true (if @p v has one entry per particle).
    template <typename T>
    void compact(std::vector<T> &v, const std::vector<char> &keep)
    {
      if (v.size() != keep.size())
        return;
      std::size_t j = 0;
      for (std::size_t i = 0; i < v.size(); ++i)
        if (keep[i])
          v[j++] = v[i];
      v.resize(j);
    }
  } // namespace

  OpenFace open_face(const Scene &scene)
  {
    const int dim = scene.dimension;
    int       axis = -1, nonzero = 0;
    for (int d = 0; d < dim; ++d)
      if (scene.gravity[d] != 0)
        axis = d, ++nonzero;
    // the face whose outward normal points against gravity
    const int top = nonzero == 1 ? 2 * axis + (scene.gravity[axis] < 0 ? 1 : 0) : -1;
    OpenFace  open;
    for (int f = 0; f < 2 * dim; ++f)
    {
      const BoundaryKind kind = scene.boundary[f];
      require(kind != BoundaryKind::slip, "Domain/" + std::string(face_names[f]) + " boundary", "slip",
              "SPH walls are BCE markers with the no-slip mirror (Eq. 59-60); allowed: no slip, periodic, and "
              "outflow on the open top of a free-surface scene");
      if (kind != BoundaryKind::inflow && kind != BoundaryKind::outflow)
        continue;
      const std::string where = top >= 0 ? std::string("here the ") + face_names[top] + " face"
                                         : std::string("none here: Forces/Gravity is not along one axis");
      require(kind == BoundaryKind::outflow && f == top && scene.fluid_region.has_value(),
              "Domain/" + std::string(face_names[f]) + " boundary", kind == BoundaryKind::inflow ? "inflow" : "outflow",
              "SPH has no inflow faces and takes outflow only as the open top of a free-surface scene: the face "
              "opposite to gravity (" + where + ") with Fluids/Initial region of fluid 1 set; elsewhere allowed: "
              "no slip, periodic");
      open.face     = f;
      open.axis     = f / 2;
      open.upper    = f % 2 == 1;
      open.position = open.upper ? scene.domain.upper[open.axis] : scene.domain.lower[open.axis];
      open.name     = face_names[f];
    }
    return open;
  }

  template <int dim>
  std::size_t remove_beyond(const OpenFace &open, HostParticles<dim> &P)
  {
    if (!open.active())
      return 0;
    std::vector<char> keep(P.size(), 1);
    std::size_t       removed = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.kind[i] == ParticleKind::fluid && open.beyond(P.x[i][open.axis]))
        keep[i] = 0, ++removed;
    if (removed == 0)
      return 0;
    compact(P.x, keep), compact(P.u, keep), compact(P.p, keep), compact(P.rho, keep);
    compact(P.wall_velocity, keep), compact(P.wall_acceleration, keep), compact(P.normal, keep);
    compact(P.body, keep);
    compact(P.kind, keep);
    return removed;
  }

  template std::size_t remove_beyond<2>(const OpenFace &, HostParticles<2> &);
  template std::size_t remove_beyond<3>(const OpenFace &, HostParticles<3> &);
} // namespace twinflow::sph
