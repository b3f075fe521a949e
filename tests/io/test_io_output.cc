// Tests of twinflow::io, part 2: run summary (JSON validity and escaping,
// table), particle VTU output (2D, 3D), PVD series and the monitor plots.
#include <twinflow/io/csv_monitor.h>
#include <twinflow/io/json_writer.h>
#include <twinflow/io/particle_output.h>
#include <twinflow/io/plots.h>
#include <twinflow/io/pvd_series.h>
#include <twinflow/io/summary.h>

#include <deal.II/base/timer.h>

#include "io_test_utils.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace fs = std::filesystem;
using namespace twinflow::io;
using namespace twinflow_test;

// ------------------------------------------------------------------------- summary

TEST(RunSummary, WritesValidEscapedJson)
{
  EXPECT_EQ(json_quote("a\"b\\c\n\t\x01"), "\"a\\\"b\\\\c\\n\\t\\u0001\"");
  EXPECT_EQ(json_number(0.1), "0.1");
  EXPECT_EQ(json_number(std::nan("")), "null");
  // the checker itself rejects malformed JSON
  EXPECT_TRUE(JsonChecker(R"({"a": [1, -2.5e-3, "x\"y", null, true]})").valid());
  for (const char *bad : {R"({"a": 1,})", R"({"a" 1})", "[1 2]", R"(["a\q"])", "[01]", "[nan]"})
    EXPECT_FALSE(JsonChecker(bad).valid()) << bad;

  TempDir      dir;
  const std::string tricky = "dam \"break\" C:\\runs\\new\n\ttab";

  dealii::TimerOutput timer(MPI_COMM_WORLD, std::cout, dealii::TimerOutput::never,
                            dealii::TimerOutput::wall_times);
  for (int i = 0; i < 3; ++i)
    {
      dealii::TimerOutput::Scope scope(timer, "assemble \"velocity\"");
    }

  RunSummary summary;
  summary.set_method("fem");
  summary.set_dimension(2);
  summary.set_scene(tricky);
  summary.set_cells(1024);
  summary.set_dofs("velocity", 8450);
  summary.set_dofs("pressure", 1089);
  summary.set_steps(100);
  summary.set_final_time(0.5);
  summary.set_wall_time(12.5);
  summary.set_timer_sections(timer);
  summary.set_timer_section("output", 0.5, 4);
  summary.set_monitor_value("drag", 3.25);
  summary.set_monitor_value("kinetic energy", std::nan("")); // written as null
  summary.add_error("front \"x\"", 1.1, 1.0, 0.2, "Martin & Moyce\\1952");
  summary.add_error("lift", 0.5, 0.25, 0.1);
  SeriesError series;
  series.rms_error = 0.1;
  series.rms_relative_error = 0.05;
  series.n_samples = 11;
  summary.add_series_error("y(t)", series, std::nullopt, "analytic");
  summary.set_extra("note", tricky);
  summary.set_extra("cfl", 0.4);
  summary.set_extra("refinements", 5);
  summary.set_extra("adaptive", true);
  summary.set_extra("cfl", 0.45); // replaces
  EXPECT_FALSE(summary.all_errors_within_tolerance()); // "lift" is off by 100 %

  const std::string path = dir / "out/summary.json";
  summary.write_json(path);
  const std::string text = slurp(path);
  EXPECT_TRUE(JsonChecker(text).valid()) << text;
  EXPECT_NE(text.find(R"("scene": "dam \"break\" C:\\runs\\new\n\ttab")"), std::string::npos)
    << text;
  EXPECT_NE(text.find(R"("dofs_total": 9539)"), std::string::npos);
  EXPECT_NE(text.find(R"("kinetic energy": null)"), std::string::npos);
  EXPECT_EQ(text.find("\"cfl\": 0.4,"), std::string::npos); // replaced, not duplicated

  if (!have_python_with("json"))
    GTEST_SKIP() << "/usr/bin/python3 not available for the JSON parse check";
  const std::string check = dir / "check.py";
  {
    std::ofstream py(check);
    py << R"(import json, sys
d = json.load(open(sys.argv[1]))
assert d["scene"] == 'dam "break" C:\\runs\\new\n\ttab', d["scene"]
assert d["extra"]["note"] == d["scene"]
assert d["method"] == "fem" and d["dimension"] == 2
assert d["size"]["dofs"] == {"velocity": 8450, "pressure": 1089}
assert d["size"]["particles"] is None
assert d["cost"]["sections"]['assemble "velocity"']["calls"] == 3
assert d["cost"]["sections"]["output"]["wall_time_s"] == 0.5
assert d["monitors"]["drag"] == 3.25 and d["monitors"]["kinetic energy"] is None
e = d["errors"]
assert len(e) == 3 and e[0]["quantity"] == 'front "x"' and abs(e[0]["relative_error"] - 0.1) < 1e-12
assert e[0]["passed"] and not e[1]["passed"] and e[2]["tolerance"] is None
assert e[0]["note"] == "Martin & Moyce\\1952" and e[2]["series"]["n_samples"] == 11
assert d["all_within_tolerance"] is False
assert d["extra"] == {"note": d["scene"], "cfl": 0.45, "refinements": 5, "adaptive": True}
)";
  }
  EXPECT_EQ(std::system(("/usr/bin/python3 " + check + " " + path).c_str()), 0) << text;
}

TEST(RunSummary, PrintsTable)
{
  RunSummary summary;
  summary.set_method("sph");
  summary.set_dimension(3);
  summary.set_scene("dam_break");
  summary.set_particles(250000);
  summary.set_steps(1000);
  summary.set_wall_time(80.0);
  summary.set_timer_section("neighbour search", 30.0, 1000);
  summary.add_error("front position", 0.98, 1.0, 0.05);
  std::ostringstream out;
  summary.print_table(out);
  const std::string s = out.str();
  EXPECT_NE(s.find("SPH"), std::string::npos) << s;
  EXPECT_NE(s.find("250000 particles"), std::string::npos) << s;
  EXPECT_NE(s.find("neighbour search"), std::string::npos) << s;
  EXPECT_NE(s.find("37.5%"), std::string::npos) << s;
  EXPECT_NE(s.find("ok"), std::string::npos) << s;
  EXPECT_NE(s.find("1m 20s"), std::string::npos) << s;
}

// ------------------------------------------------------------------ particle VTU

namespace
{
  unsigned long
  number_of_points(const std::string &vtu)
  {
    const std::string text = slurp(vtu);
    std::smatch       m;
    static const std::regex re("NumberOfPoints=\"([0-9]+)\"");
    if (!std::regex_search(text, m, re))
      return static_cast<unsigned long>(-1);
    return std::stoul(m[1]);
  }

  template <int dim>
  void
  check_particle_vtu(const std::size_t n)
  {
    TempDir                              dir;
    std::vector<std::array<double, dim>> x(n), v(n);
    std::vector<float>                   rho(n);
    std::vector<int>                     type(n);
    for (std::size_t p = 0; p < n; ++p)
      {
        for (int d = 0; d < dim; ++d)
          {
            x[p][d] = 0.1 * p + d;
            v[p][d] = -1.0 * d;
          }
        rho[p]  = 1000.0f + p;
        type[p] = p % 2;
      }
    ParticleOutput<dim> output;
    output.set_positions(x);
    output.add_scalar("density", rho);
    output.add_vector("velocity", v);
    output.add_scalar("type", type);
    output.set_time(0.25, 7);
    EXPECT_EQ(output.n_particles(), n);
    EXPECT_EQ(output.data_names().size(), dim + 2u);
    ASSERT_EQ(output.nonscalar_data_ranges().size(), 1u);
    EXPECT_EQ(std::get<0>(output.nonscalar_data_ranges()[0]), 1u);
    EXPECT_EQ(std::get<1>(output.nonscalar_data_ranges()[0]), static_cast<unsigned>(dim));

    const auto patches = output.build_patches();
    ASSERT_EQ(patches.size(), n);
    EXPECT_DOUBLE_EQ(patches[n - 1].vertices[0][dim - 1], 0.1 * (n - 1) + dim - 1);
    EXPECT_FLOAT_EQ(patches[2].data(0, 0), 1002.0f);
    EXPECT_FLOAT_EQ(patches[2].data(dim + 1, 0), 0.0f);

    const std::string file = dir / "sph/particles_0007.vtu";
    output.write_vtu(file);
    EXPECT_EQ(number_of_points(file), n);
    const std::string text = slurp(file);
    EXPECT_NE(text.find(R"(Name="velocity" NumberOfComponents="3")"), std::string::npos) << text;
    EXPECT_NE(text.find(R"(Name="density")"), std::string::npos);

    // flat input gives the same patches
    std::vector<double> flat;
    for (const auto &p : x)
      flat.insert(flat.end(), p.begin(), p.end());
    ParticleOutput<dim> flat_output;
    flat_output.set_positions_flat(flat);
    flat_output.add_vector_flat("velocity", flat);
    EXPECT_EQ(flat_output.build_patches()[n - 1].vertices[0], patches[n - 1].vertices[0]);

    // wrong field size
    output.add_scalar("short", std::vector<double>(n - 1));
    EXPECT_THROW(output.build_patches(), std::invalid_argument);
    EXPECT_THROW(output.add_scalar("density", rho), std::invalid_argument);
  }
} // namespace

TEST(ParticleOutput, Vtu2d)
{
  check_particle_vtu<2>(5);
}

TEST(ParticleOutput, Vtu3d)
{
  check_particle_vtu<3>(7);
}

TEST(ParticleOutput, EmptySet)
{
  TempDir           dir;
  ParticleOutput<2> output;
  output.set_positions(std::vector<std::array<double, 2>>{});
  output.add_scalar("density", std::vector<double>{});
  output.write_vtu(dir / "empty.vtu");
  EXPECT_EQ(number_of_points(dir / "empty.vtu"), 0u);
}

// ---------------------------------------------------------------------- PVD series

TEST(PvdSeries, ContainsAllRecords)
{
  TempDir   dir;
  const std::string out_dir = dir / "fem";
  PvdSeries series(out_dir, "solution");
  series.add(0.0, "solution_000.pvtu");
  series.add(0.125, out_dir + "/solution_001.pvtu");        // made relative
  series.add(0.25, (fs::path(out_dir) / "sub/p_2.vtu").string());
  ASSERT_EQ(series.records().size(), 3u);
  EXPECT_EQ(series.records()[1].second, "solution_001.pvtu");
  EXPECT_EQ(series.records()[2].second, "sub/p_2.vtu");
  EXPECT_EQ(series.pvd_path(), out_dir + "/solution.pvd");

  const std::string text = slurp(series.pvd_path());
  EXPECT_NE(text.find("<Collection>"), std::string::npos) << text;
  for (const char *f : {"solution_000.pvtu", "\"solution_001.pvtu\"", "\"sub/p_2.vtu\""})
    EXPECT_NE(text.find(f), std::string::npos) << f << "\n" << text;
  std::size_t count = 0;
  for (auto pos = text.find("<DataSet"); pos != std::string::npos;
       pos      = text.find("<DataSet", pos + 1))
    ++count;
  EXPECT_EQ(count, 3u);
  EXPECT_NE(text.find("timestep=\"0.125\""), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(series.pvd_path() + ".tmp"));
}

// --------------------------------------------------------------------------- plots

TEST(Plots, MonitorPngsForFemAndSph)
{
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
  TempDir dir;
  for (const std::string method : {"fem", "sph"})
    {
      CsvMonitor m(dir / (method + "/front.csv"), {"time", "x_front", "height"}, {"s", "m", "m"});
      for (int i = 0; i <= 10; ++i)
        m.append({0.1 * i, 1.0 + 0.2 * i + (method == "sph" ? 0.01 : 0.0), 1.0 - 0.05 * i});
    }
  {
    std::ofstream f(dir / "ref.csv");
    f << "# reference\nT,Z\n0,1\n1,3\n";
  }
  // a missing interpreter is a warning and a `false`, never an error
  ::setenv("TWINFLOW_PYTHON", "/nonexistent/python3", 1);
  EXPECT_FALSE(make_plots(dir.path.string()));
  ::unsetenv("TWINFLOW_PYTHON");

  if (plot_script_path().empty() || !have_python_with("matplotlib"))
    {
      EXPECT_FALSE(make_plots(dir.path.string()));
      GTEST_SKIP() << "plot script or /usr/bin/python3 with matplotlib not available";
    }
  EXPECT_TRUE(make_plots(dir.path.string()));
  EXPECT_TRUE(fs::exists(dir / "plots/front.png"));
  EXPECT_TRUE(make_monitor_plots({dir / "fem", dir / "sph"},
                                 {"--output-dir", dir / "cmp", "--reference", dir / "ref.csv",
                                  "--ref-x", "T", "--ref-y", "Z", "--monitor", "front",
                                  "--column", "x_front"}));
  EXPECT_TRUE(fs::exists(dir / "cmp/front.png"));
}

// --hline MONITOR:COLUMN=VALUE[:LABEL] (what twinflow passes for References/Drag and Lift
// coefficient): the PNG differs from the one without it, a column named with or without its unit
// gives no warning, an unknown column a warning, and a malformed --hline an error naming it.
TEST(Plots, ReferenceHorizontalLines)
{
  TempDir dir;
  for (const std::string method : {"fem", "sph"})
    {
      CsvMonitor m(dir / (method + "/forces.csv"), {"time", "Fx", "C_d", "C_l"}, {"s", "N", "-", "-"});
      for (int i = 0; i <= 10; ++i)
        m.append({0.1 * i, 1.0, 5.0 + 0.05 * i + (method == "sph" ? 0.02 : 0.0), 0.001 * i});
    }
  if (plot_script_path().empty() || !have_python_with("matplotlib"))
    GTEST_SKIP() << "plot script or /usr/bin/python3 with matplotlib not available";

  // the script itself, with its stdout and stderr in files; returns the exit status
  const auto script = [&](const std::string &arguments, const std::string &name) {
    const std::string command = shell_quote("/usr/bin/python3") + " " +
                                shell_quote(plot_script_path()) + " " + arguments + " >" +
                                shell_quote(dir / (name + ".out")) + " 2>" +
                                shell_quote(dir / (name + ".err"));
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  const std::string fem = shell_quote(dir / "fem"), sph = shell_quote(dir / "sph");

  ASSERT_EQ(script(fem + " --output-dir " + shell_quote(dir / "plain"), "plain"), 0);
  ASSERT_EQ(script(fem + " " + sph + " --output-dir " + shell_quote(dir / "lines") +
                     " --hline 'forces:C_d=5.3:body-fitted reference' --hline 'forces:C_l [-]=0.004'",
                   "lines"),
            0)
    << slurp(dir / "lines.err");
  EXPECT_TRUE(fs::exists(dir / "lines/forces.png"));
  EXPECT_EQ(slurp(dir / "lines.err"), "");
  ASSERT_EQ(script(fem + " --output-dir " + shell_quote(dir / "one") + " --hline forces:C_d=5.3",
                   "one"),
            0);
  ASSERT_TRUE(fs::exists(dir / "one/forces.png"));
  EXPECT_NE(slurp(dir / "one/forces.png"), slurp(dir / "plain/forces.png"))
    << "the reference line is not drawn";

  EXPECT_EQ(script(fem + " --output-dir " + shell_quote(dir / "unknown") + " --hline forces:C_x=1",
                   "unknown"),
            0);
  EXPECT_NE(slurp(dir / "unknown.err").find("warning: monitor 'forces' has no column 'C_x'"),
            std::string::npos)
    << slurp(dir / "unknown.err");

  for (const std::string bad : {"forces:C_d", "forces:C_d=abc", ":C_d=1"})
    {
      EXPECT_EQ(script(fem + " --output-dir " + shell_quote(dir / "bad") + " --hline " + shell_quote(bad),
                       "bad"),
                2)
        << bad;
      const std::string err = slurp(dir / "bad.err");
      EXPECT_NE(err.find("error: --hline '" + bad + "'"), std::string::npos) << bad << "\n" << err;
      EXPECT_NE(err.find("expected MONITOR:COLUMN=VALUE[:LABEL]"), std::string::npos) << err;
    }
  EXPECT_FALSE(fs::exists(dir / "bad/forces.png"));

  // through make_monitor_plots(), as twinflow's main calls it
  EXPECT_TRUE(make_monitor_plots({dir / "fem"}, {"--output-dir", dir / "app", "--hline",
                                                 "forces:C_d=5.3:reference"}));
  EXPECT_TRUE(fs::exists(dir / "app/forces.png"));
  EXPECT_FALSE(make_monitor_plots({dir / "fem"}, {"--output-dir", dir / "app2", "--hline", "forces:C_d"}));
}
