// Tests of twinflow::io, part 1: CSV monitors and reader, reference-data
// comparison, progress lines. (Part 2, output files: test_io_output.cc.)
#include <twinflow/io/csv_monitor.h>
#include <twinflow/io/progress.h>
#include <twinflow/io/reference_data.h>

#include "io_test_utils.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace twinflow::io;
using namespace twinflow_test;

// ----------------------------------------------------------------------------- CSV

TEST(CsvMonitor, RoundTripWithHeaderAndUnits)
{
  TempDir           dir;
  const std::string path = dir / "sub/forces.csv"; // directory is created
  {
    CsvMonitor monitor(path, {"time", "drag", "x_front"}, {"s", "N", ""});
    EXPECT_EQ(monitor.name(), "forces");
    EXPECT_TRUE(monitor.is_writer());
    monitor.append({0.0, 1.0 / 3.0, -2.5e-7});
    monitor.append(0.125, {std::acos(-1.0), 12345.678901234});
    EXPECT_EQ(monitor.n_rows(), 2u);
    // written and flushed while the monitor is still open
    EXPECT_EQ(lines_of(path).size(), 4u);
    EXPECT_THROW(monitor.append({1.0, 2.0}), std::invalid_argument);
  }
  const auto lines = lines_of(path);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "# twinflow monitor: forces");
  EXPECT_EQ(lines[1], "time [s],drag [N],x_front");
  EXPECT_EQ(lines[2], "0.000000000000e+00,3.333333333333e-01,-2.500000000000e-07");

  const CsvTable table = read_csv(path);
  ASSERT_EQ(table.n_columns(), 3u);
  ASSERT_EQ(table.n_rows(), 2u);
  EXPECT_EQ(table.names, (std::vector<std::string>{"time", "drag", "x_front"}));
  EXPECT_EQ(table.units, (std::vector<std::string>{"s", "N", ""}));
  EXPECT_EQ(table.headers[1], "drag [N]");
  EXPECT_EQ(table.column("drag [N]"), table.column("drag"));
  EXPECT_NEAR(table.column("drag")[0], 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(table.column("drag")[1], std::acos(-1.0), 1e-11);
  EXPECT_NEAR(table.column("x_front")[1], 12345.678901234, 1e-7);
  EXPECT_DOUBLE_EQ(table.column("time")[1], 0.125);
  EXPECT_THROW(table.column("lift"), std::out_of_range);
}

TEST(CsvMonitor, RejectsInvalidArguments)
{
  TempDir dir;
  EXPECT_THROW(CsvMonitor(dir / "a.csv", {"time", "drag"}, {"s"}), std::invalid_argument);
  EXPECT_THROW(CsvMonitor(dir / "b.csv", {"time", "a,b"}), std::invalid_argument);
  EXPECT_THROW(CsvMonitor(dir / "c.csv", {}), std::invalid_argument);
  CsvMonitor named(dir / "d.csv", {"t"}, {}, MPI_COMM_WORLD, "my monitor");
  EXPECT_EQ(lines_of(dir / "d.csv").at(0), "# twinflow monitor: my monitor");
}

TEST(CsvReader, ReadsReferenceFormatAndReportsErrors)
{
  TempDir dir;
  {
    std::ofstream f(dir / "ref.csv");
    f << "# Martin & Moyce (1952), Table 2\n# T = t*sqrt(2 g / a)\nT,Z\n0.41,1.11\n  0.84 , 1.22\r\n"
      << "\n1.19,1.44\n";
  }
  const CsvTable t = read_csv(dir / "ref.csv");
  EXPECT_EQ(t.names, (std::vector<std::string>{"T", "Z"}));
  EXPECT_EQ(t.n_rows(), 3u);
  EXPECT_DOUBLE_EQ(t.column("Z")[1], 1.22);

  {
    std::ofstream f(dir / "bad.csv");
    f << "a,b\n1,2\n3\n";
  }
  EXPECT_THROW(read_csv(dir / "bad.csv"), std::runtime_error);
  {
    std::ofstream f(dir / "bad2.csv");
    f << "a,b\n1,x\n";
  }
  EXPECT_THROW(read_csv(dir / "bad2.csv"), std::runtime_error);
  EXPECT_THROW(read_csv(dir / "missing.csv"), std::runtime_error);
}

// ------------------------------------------------------------------- reference data

TEST(ReferenceData, LinearInterpolation)
{
  const std::vector<double> x{0.0, 1.0, 3.0}, y{1.0, 3.0, -1.0};
  EXPECT_DOUBLE_EQ(interpolate_linear(x, y, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(interpolate_linear(x, y, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(interpolate_linear(x, y, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(interpolate_linear(x, y, 3.0), -1.0);
  EXPECT_THROW(interpolate_linear(x, y, 3.1), std::out_of_range);
  EXPECT_THROW(interpolate_linear(x, y, -0.1), std::out_of_range);

  // unsorted input is sorted; duplicates are rejected
  const ReferenceSeries ref({3.0, 0.0, 1.0}, {-1.0, 1.0, 3.0});
  EXPECT_DOUBLE_EQ(ref(0.5), 2.0);
  EXPECT_DOUBLE_EQ(ref.x_min(), 0.0);
  EXPECT_DOUBLE_EQ(ref.x_max(), 3.0);
  EXPECT_TRUE(ref.covers(3.0));
  EXPECT_FALSE(ref.covers(3.5));
  EXPECT_THROW(ReferenceSeries({0.0, 0.0}, {1.0, 2.0}), std::invalid_argument);
}

TEST(ReferenceData, RmsErrorOfShiftedLine)
{
  // reference y = 2t on [0, 1] (11 points), simulation y = 2t + 0.1 on [0, 2]
  std::vector<double> tr, yr, ts, ys;
  for (int i = 0; i <= 10; ++i)
    {
      tr.push_back(0.1 * i);
      yr.push_back(2.0 * tr.back());
    }
  for (int i = 0; i <= 200; ++i)
    {
      ts.push_back(0.01 * i);
      ys.push_back(2.0 * ts.back() + 0.1);
    }
  const ReferenceSeries ref(tr, yr, "2t");

  for (const auto where : {SamplePoints::reference, SamplePoints::simulation})
    {
      const SeriesError e = compare_series(ts, ys, ref, where);
      EXPECT_NEAR(e.rms_error, 0.1, 1e-12);
      EXPECT_NEAR(e.max_error, 0.1, 1e-12);
      EXPECT_DOUBLE_EQ(e.t_begin, 0.0);
      EXPECT_DOUBLE_EQ(e.t_end, 1.0);
      EXPECT_NEAR(e.max_relative_error, 0.1 / 2.0, 1e-12);
    }
  const SeriesError e = compare_series(ts, ys, ref);
  EXPECT_EQ(e.n_samples, 11u);
  double sum_r2 = 0; // sum of (2 t_i)^2 at the reference points
  for (const double y : yr)
    sum_r2 += y * y;
  EXPECT_NEAR(e.rms_relative_error, std::sqrt(11 * 0.01 / sum_r2), 1e-12);
  EXPECT_EQ(compare_series(ts, ys, ref, SamplePoints::simulation).n_samples, 101u);

  // no overlap
  const SeriesError none = compare_series({5.0, 6.0}, {1.0, 1.0}, ref);
  EXPECT_EQ(none.n_samples, 0u);
  EXPECT_TRUE(std::isnan(none.rms_error));
}

TEST(ReferenceData, FromCsvWithScaling)
{
  TempDir dir;
  {
    std::ofstream f(dir / "ref.csv");
    f << "# comment\nT,Z\n0,1\n1,2\n2,4\n";
  }
  const auto ref = ReferenceSeries::from_csv(dir / "ref.csv", "T", "Z", 0.5, 10.0, 1.0);
  EXPECT_DOUBLE_EQ(ref.x_max(), 1.0);
  EXPECT_DOUBLE_EQ(ref(0.25), 16.0); // between (0, 11) and (0.5, 21)
  EXPECT_THROW(ReferenceSeries::from_csv(dir / "ref.csv", "T", "W"), std::out_of_range);
}

// ------------------------------------------------------------------------ progress

TEST(Progress, FormatsAndThrottles)
{
  EXPECT_EQ(format_duration(12.1), "12.1 s");
  EXPECT_EQ(format_duration(77.0), "1m 17s");
  EXPECT_EQ(format_duration(7380.0), "2h 03m");
  EXPECT_EQ(format_duration(-1.0), "--");

  std::ostringstream out;
  ProgressReporter   progress(0.0, 2.5, out, 0.0);
  EXPECT_TRUE(progress.update(0.34, 120, "dt = 1e-3"));
  const std::string line = out.str();
  EXPECT_EQ(line.rfind("step 120  t = 0.3400 / 2.5 s (13.6 %)  elapsed ", 0), 0u) << line;
  EXPECT_NE(line.find("  ETA "), std::string::npos) << line;
  EXPECT_NE(line.find("  dt = 1e-3\n"), std::string::npos) << line;

  std::ostringstream slow_out;
  ProgressReporter   slow(0.0, 1.0, slow_out, MPI_COMM_WORLD, 1000.0);
  EXPECT_FALSE(slow.update(0.1, 1));
  EXPECT_TRUE(slow.update(0.2, 2, "", true));
  slow.finish();
  slow.finish();
  const std::string s = slow_out.str();
  EXPECT_NE(s.find("step 2  t = 0.2000 / 1 s (20.0 %)"), std::string::npos) << s;
  EXPECT_EQ(s.find("step 1 "), std::string::npos) << s;
  EXPECT_NE(s.find("done: step 2  t = 0.2 s"), std::string::npos) << s;
  EXPECT_EQ(s.find("done:"), s.rfind("done:")) << s;
}
