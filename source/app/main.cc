// twinflow: run a scene (.prm) with the FEM and/or SPH solvers.
#include <twinflow/core/errors.h>
#include <twinflow/core/scene.h>
#include <twinflow/solids/coupling.h>
#include <twinflow/fem/fem_simulation.h>
#include <twinflow/io/front_reference.h>
#include <twinflow/io/mpi_utils.h>
#include <twinflow/io/plots.h>
#include <twinflow/sph/sph_simulation.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace
{
  const char *usage = R"(twinflow — free-surface and fluid-solid flow, Eulerian (FEM) and Lagrangian (SPH)

usage:
  twinflow SCENE.prm [--set 'Subsection/Entry=value' ...] [-o OUTPUT_DIR] [--check]
                                       run a scene (mpirun -np N twinflow ... distributes the FEM)
  twinflow --print-parameters          print every parameter with its documentation and default
  twinflow --help                      this text

  --set 'A/B/Entry=value'   override an entry of the scene file after it is read, e.g.
                            --set 'FEM/Global refinements=3' or --set 'Scene/End time=0.5';
                            the path names the subsections, the last part is the entry
                            (top-level entries have no '/'). Checked like the file: an
                            unknown subsection or entry, or a value outside the entry's
                            pattern, is an input error. Several --set are applied in order.
  -o OUTPUT_DIR             write the results there instead of Scene/Output directory
  --check                   read the scene and the overrides, check them, run nothing

Results go to the scene's 'Output directory' (or OUTPUT_DIR): one folder per method with
ParaView files, CSV monitors, summary.json and PNG plots. Studies (sweeps of any entries,
one folder per case, a table and error-against-cost plots): scripts/study.py --help.
)";

  void declare_all(dealii::ParameterHandler &prm)
  {
    twinflow::declare_scene_parameters(prm);
    twinflow::fem::FemParameters::declare(prm);
    twinflow::sph::SphParameters::declare(prm);
  }

  /// deal.II's message of an exception without the stack trace.
  std::string message_of(const dealii::ExceptionBase &e)
  {
    std::ostringstream s;
    e.print_info(s);
    std::string m = s.str();
    while (!m.empty() && (m.back() == '\n' || m.back() == ' '))
      m.pop_back();
    return m.erase(0, std::min(m.find_first_not_of(" \n"), m.size()));
  }

  std::string trim(const std::string &s)
  {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos)
      return "";
    return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
  }

  std::string join(const std::set<std::string> &names)
  {
    std::string r;
    for (const auto &n : names)
      r += (r.empty() ? "" : ", ") + n;
    return r.empty() ? "(none)" : r;
  }

  /// One command-line override `--set 'Sub/Sub/Entry=value'`.
  struct Override
  {
    std::string              text;  ///< as given
    std::vector<std::string> path;  ///< subsections, outermost first
    std::string              entry;
    std::string              value;

    std::string full_name() const
    {
      std::string r;
      for (const auto &p : path)
        r += p + "/";
      return r + entry;
    }
  };

  /// Splits `A/B/Entry = value` (whitespace around '=', '/' and the ends trimmed).
  Override parse_override(const std::string &text)
  {
    Override o;
    o.text = text;
    const std::string prefix = "--set '" + text + "': ";
    const auto eq = text.find('=');
    if (eq == std::string::npos)
      throw twinflow::InputError(prefix + "expected 'Subsection/.../Entry=value' (no '=' found), "
                                          "e.g. --set 'FEM/Global refinements=3'");
    o.value = trim(text.substr(eq + 1));
    std::vector<std::string> parts;
    std::string key = text.substr(0, eq);
    for (std::size_t begin = 0;;)
    {
      const auto slash = key.find('/', begin);
      parts.push_back(trim(key.substr(begin, slash == std::string::npos ? std::string::npos : slash - begin)));
      if (slash == std::string::npos)
        break;
      begin = slash + 1;
    }
    for (const auto &p : parts)
      if (p.empty())
        throw twinflow::InputError(prefix + "empty " + (&p == &parts.back() ? "entry" : "subsection") +
                                   " name in '" + trim(key) +
                                   "'; expected 'Subsection/.../Entry=value', e.g. --set 'FEM/Global refinements=3'");
    o.entry = parts.back();
    parts.pop_back();
    o.path = parts;
    return o;
  }

  /// The declared subsections and entries, by subsection path ("" is the top level, "FEM/Navier-Stokes"
  /// a nested one), read from the parameter handler's own listing.
  struct Catalog
  {
    std::map<std::string, std::set<std::string>> subsections, entries;

    explicit Catalog(const dealii::ParameterHandler &prm)
    {
      std::ostringstream listing;
      prm.print_parameters(listing, dealii::ParameterHandler::ShortPRM);
      std::istringstream in(listing.str());
      std::vector<std::string> stack;
      const auto joined = [&stack]() {
        std::string r;
        for (const auto &s : stack)
          r += (r.empty() ? "" : "/") + s;
        return r;
      };
      subsections[""];
      entries[""];
      for (std::string line; std::getline(in, line);)
      {
        line = trim(line);
        if (line.rfind("subsection ", 0) == 0)
        {
          const std::string name = trim(line.substr(11));
          subsections[joined()].insert(name);
          stack.push_back(name);
          subsections[joined()];
          entries[joined()];
        }
        else if (line == "end" && !stack.empty())
          stack.pop_back();
        else if (line.rfind("set ", 0) == 0 && line.find('=') != std::string::npos)
          entries[joined()].insert(trim(line.substr(4, line.find('=') - 4)));
      }
    }
  };

  /// Applies @p o to @p prm with the checks of the file parser: the subsections and the entry must be
  /// declared, and the value must match the entry's pattern.
  void apply_override(dealii::ParameterHandler &prm, const Override &o, const Catalog &catalog)
  {
    using twinflow::InputError;
    const std::string prefix = "--set '" + o.text + "': ";
    const auto where = [](const std::string &path) {
      return path.empty() ? std::string("at the top level") : "in subsection '" + path + "'";
    };
    std::string path;
    for (const auto &sub : o.path)
    {
      const auto &allowed = catalog.subsections.at(path);
      if (!allowed.count(sub))
        throw InputError(prefix + "no subsection '" + sub + "' " + where(path) + "; allowed subsections: " +
                         join(allowed) + "\n(twinflow --print-parameters lists every subsection and entry "
                                         "with its allowed values)");
      path += (path.empty() ? "" : "/") + sub;
    }
    const auto &entries = catalog.entries.at(path);
    if (!entries.count(o.entry))
    {
      std::string msg = prefix + "no entry '" + o.entry + "' " + where(path) + "; allowed entries: " + join(entries);
      if (!catalog.subsections.at(path).empty())
        msg += "; subsections: " + join(catalog.subsections.at(path));
      throw InputError(msg + "\n(twinflow --print-parameters lists every subsection and entry with its allowed values)");
    }
    for (const auto &sub : o.path)
      prm.enter_subsection(sub);
    std::string error;
    try
    {
      prm.set(o.entry, o.value);
    }
    catch (const dealii::ExceptionBase &e)
    {
      error = message_of(e);
    }
    for (std::size_t i = 0; i < o.path.size(); ++i)
      prm.leave_subsection();
    if (!error.empty())
    {
      // deal.II: "The string <v> does not match the given pattern <P>." -> P
      const std::string key = "pattern <";
      const auto        b   = error.find(key);
      const auto        e   = error.rfind('>');
      const std::string pattern =
        b != std::string::npos && e != std::string::npos && e > b ? error.substr(b + key.size(), e - b - key.size()) : error;
      throw InputError(prefix + "the value '" + o.value + "' for the entry '" + o.full_name() +
                       "' does not match its pattern; allowed: " + pattern);
    }
  }

  /// Extra arguments of scripts/plot_monitors.py for the scene's references: a dashed
  /// horizontal line at References/Drag coefficient (Lift coefficient) on the C_d (C_l)
  /// subplot of the forces monitor, FEM and SPH alike (none without that monitor).
  std::vector<std::string> plot_arguments(const twinflow::Scene &scene)
  {
    std::vector<std::string> arguments;
    const auto hline = [&](const char *column, const std::optional<double> &value)
    {
      if (!value || !scene.monitors_contain("forces"))
        return;
      std::ostringstream spec;
      spec.precision(12);
      spec << "forces:" << column << '=' << *value << ":reference " << column << " = " << *value;
      arguments.insert(arguments.end(), {"--hline", spec.str()});
    };
    // the measured error beside each run's label (from its summary.json)
    const auto error_label = [&](const char *target, const char *quantity)
    { arguments.insert(arguments.end(), {"--error-label", std::string(target) + '=' + quantity}); };
    hline("C_d", scene.reference_drag);
    hline("C_l", scene.reference_lift);
    if (scene.reference_drag)
      error_label("forces:C_d", "drag coefficient C_d");
    if (scene.reference_lift)
      error_label("forces:C_l", "lift coefficient C_l");
    // the front table as points on x_front(t), and a figure in its own axes Z(T)
    if (!scene.reference_front_file.empty())
    {
      const twinflow::io::FrontScale scale = twinflow::io::front_scale(scene);
      const auto number = [](const double v)
      {
        std::ostringstream out;
        out.precision(12);
        out << v;
        return out.str();
      };
      arguments.insert(arguments.end(),
                       {"--reference", scene.reference_front_file, "--ref-x", "T", "--ref-y", "Z", "--monitor",
                        "front", "--column", "x_front", "--ref-x-scale", number(scale.time),
                        "--ref-y-scale", number(scale.length), "--ref-x-label", "T = t sqrt(2 g / a)",
                        "--ref-y-label", "Z = x_front / a   (a = " + number(scale.length) + " m)"});
      error_label("front:x_front", "front position x_f(t)");
      if (scene.reference_front_time_uncertainty > 0)
        arguments.insert(arguments.end(), {"--time-shift", "front:x_front=front fitted time origin delay [s]"});
    }
    // one rigid body under gravity along y: its weight on the fluid-force subplot (what the
    // vertical force of a floating body settles to)
    std::vector<const twinflow::Solid *> rigid;
    for (const auto &s : scene.solids)
      if (s.motion == twinflow::SolidMotion::rigid)
        rigid.push_back(&s);
    const double g = std::abs(scene.gravity[1]);
    if (rigid.size() == 1 && g > 0 && scene.gravity[0] == 0 && scene.gravity[2] == 0)
    {
      const double span = scene.dimension == 3 ? scene.domain.upper[2] - scene.domain.lower[2] : 1.0;
      const double m    = twinflow::solids::solid_mass_properties(*rigid.front(), scene.dimension, span).mass;
      std::ostringstream spec;
      spec.precision(12);
      spec << "body:Fy=" << m * g * (scene.gravity[1] < 0 ? 1 : -1) << ":weight m g (floating equilibrium)";
      arguments.insert(arguments.end(), {"--hline", spec.str()});
      error_label("body:Fy", "vertical fluid force against the weight");
    }
    return arguments;
  }

  int run(const std::string &file, const std::vector<Override> &overrides, const std::string &output_override,
          const bool check_only, const std::string &command_line)
  {
    using namespace twinflow;
    dealii::ParameterHandler prm;
    declare_all(prm);
    {
      std::ifstream in(file);
      if (!in)
        throw InputError("cannot open scene file '" + file + "' (no such file or not readable)");
    }
    try
    {
      prm.parse_input(file);
    }
    catch (const dealii::ExceptionBase &e)
    {
      throw InputError("in scene file '" + file + "': " + message_of(e) +
                       "\n(twinflow --print-parameters lists every subsection and entry with its allowed values)");
    }
    if (!overrides.empty())
    {
      const Catalog catalog(prm);
      for (const auto &o : overrides)
        apply_override(prm, o, catalog);
    }
    Scene scene = parse_scene(prm, file);
    fem::FemParameters fem_prm;
    fem_prm.parse(prm);
    if (!output_override.empty())
      scene.output_directory = output_override;
    sph::SphParameters sph_prm;
    sph_prm.parse(prm);

    const bool root = io::is_root_process(MPI_COMM_WORLD);
    if (root)
    {
      std::cout << "twinflow: scene '" << scene.name << "' (" << scene.dimension << "D) from " << file << std::endl;
      for (const auto &o : overrides)
        std::cout << "  --set " << o.full_name() << " = " << o.value << std::endl;
    }
    if (check_only)
    {
      if (scene.wants(Method::fem))
        fem::check_fem_scene(scene, fem_prm);
      if (root)
        std::cout << "twinflow: input ok (--check: nothing run)" << std::endl;
      return 0;
    }
    // The plot step, after the methods: monitor plots and snapshots in <output>/plots, and
    // <output>/report.md. Optional: a missing python or matplotlib gives a warning, never an
    // error.
    std::vector<std::string> method_dirs;
    const auto plot_step = [&](const std::string &stopped) {
      auto arguments = plot_arguments(scene);
      arguments.insert(arguments.end(), {"--output-dir", scene.output_directory + "/plots"});
      io::make_monitor_plots(method_dirs, arguments);
      if (!scene.snapshot_times.empty())
        io::make_snapshot_plots(scene.output_directory);
      io::make_report(scene.output_directory, file, command_line, MPI_COMM_WORLD, stopped);
    };
    // what the methods write from here on: a stop before any of it (a composition or restart
    // error) leaves the output directory as it was
    const auto started   = std::filesystem::file_time_type::clock::now();
    const auto wrote_any = [&] {
      std::error_code ec;
      for (const auto &d : method_dirs)
        for (const auto &f : std::filesystem::directory_iterator(d, ec))
          if (f.is_regular_file(ec) && f.last_write_time(ec) >= started)
            return true;
      return false;
    };
    try
    {
      if (scene.wants(Method::sph))
      {
        method_dirs.push_back(scene.output_directory + "/sph");
        sph::run_sph_scene(scene, sph_prm, method_dirs.back());
      }
      if (scene.wants(Method::fem))
      {
        // FEM first in the plots' legends
        method_dirs.insert(method_dirs.begin(), scene.output_directory + "/fem");
        fem::run_fem_scene(scene, fem_prm, method_dirs.front());
      }
    }
    catch (const std::exception &e)
    {
      // a run that stops (divergence, a body at a wall, ...) still gets its plots and a report
      // of what it wrote up to the stop; the error itself is reported by main()
      const auto *deal = dynamic_cast<const dealii::ExceptionBase *>(&e);
      if (wrote_any())
        plot_step(deal ? message_of(*deal) : std::string(e.what()));
      throw;
    }
    plot_step("");
    return 0;
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const bool root = twinflow::io::is_root_process(MPI_COMM_WORLD);
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string file, output;
  std::vector<std::string> sets;
  bool check_only = false;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    if (args[i] == "--help" || args[i] == "-h")
    {
      if (root) std::cout << usage;
      return 0;
    }
    if (args[i] == "--print-parameters")
    {
      dealii::ParameterHandler prm;
      declare_all(prm);
      if (root) prm.print_parameters(std::cout, dealii::ParameterHandler::PRM);
      return 0;
    }
    if ((args[i] == "-o" || args[i] == "--set") && i + 1 == args.size())
    {
      if (root) std::cerr << "twinflow: input error: option '" << args[i] << "' needs an argument\n" << usage;
      return 1;
    }
    if (args[i] == "-o")
      output = args[++i];
    else if (args[i] == "--set")
      sets.push_back(args[++i]);
    else if (args[i].rfind("--set=", 0) == 0)
      sets.push_back(args[i].substr(6));
    else if (args[i] == "--check")
      check_only = true;
    else if (!args[i].empty() && args[i][0] == '-')
    {
      if (root) std::cerr << "twinflow: unknown option '" << args[i] << "'\n" << usage;
      return 1;
    }
    else if (!file.empty())
    {
      if (root) std::cerr << "twinflow: input error: two scene files given ('" << file << "', '" << args[i]
                          << "'); run one scene at a time\n";
      return 1;
    }
    else
      file = args[i];
  }
  if (file.empty())
  {
    if (root) std::cerr << usage;
    return 1;
  }
  try
  {
    std::vector<Override> overrides;
    for (const auto &text : sets)
      overrides.push_back(parse_override(text));
    std::string command_line = "twinflow";
    for (const auto &a : args)
      command_line += " " + twinflow::io::shell_quote(a);
    return run(file, overrides, output, check_only, command_line);
  }
  catch (const twinflow::InputError &e)
  {
    if (root) std::cerr << "twinflow: input error: " << e.what() << std::endl;
    return 1;
  }
  catch (const dealii::ExceptionBase &e)
  {
    if (root) std::cerr << "twinflow: error: " << message_of(e) << std::endl;
    return 2;
  }
  catch (const std::exception &e)
  {
    if (root) std::cerr << "twinflow: error: " << e.what() << std::endl;
    return 2;
  }
}
