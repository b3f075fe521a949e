// Dispatch to the SPH backends compiled into this build.
#include <twinflow_sph/engine.h>

#include <stdexcept>

namespace twinflow::sph
{
  namespace cpu
  {
    template <int dim>
    std::unique_ptr<Engine<dim>> create_engine(const DomainBox<dim> &, const EngineSettings &);
  }
#ifdef TWINFLOW_WITH_CUDA
  namespace cuda
  {
    template <int dim>
    std::unique_ptr<Engine<dim>> create_engine(const DomainBox<dim> &, const EngineSettings &);
  }
#endif

  std::vector<std::string> available_backends()
  {
#ifdef TWINFLOW_WITH_CUDA
    return {"cpu", "cuda"};
#else
    return {"cpu"};
#endif
  }

  template <int dim>
  std::unique_ptr<Engine<dim>> make_engine(const std::string &backend, const DomainBox<dim> &box,
                                           const EngineSettings &settings)
  {
    if (backend == "cpu")
      return cpu::create_engine<dim>(box, settings);
#ifdef TWINFLOW_WITH_CUDA
    if (backend == "cuda")
      return cuda::create_engine<dim>(box, settings);
#endif
    throw std::invalid_argument("SPH backend '" + backend + "' is not part of this build (available: cpu" +
                                std::string(available_backends().size() > 1 ? ", cuda" : "") + ")");
  }

  template std::unique_ptr<Engine<2>> make_engine<2>(const std::string &, const DomainBox<2> &, const EngineSettings &);
  template std::unique_ptr<Engine<3>> make_engine<3>(const std::string &, const DomainBox<3> &, const EngineSettings &);
} // namespace twinflow::sph
