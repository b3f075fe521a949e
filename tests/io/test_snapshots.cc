// Snapshot times (io/snapshots.h): file names shared by FEM and SPH, and the schedule that
// writes each snapshot once, at the first step at or after its time, also across a restart.
#include <twinflow/io/snapshots.h>

#include <gtest/gtest.h>

using twinflow::io::snapshot_file_name;
using twinflow::io::SnapshotSchedule;

TEST(Snapshots, FileNameHasThreeDecimals)
{
  EXPECT_EQ(snapshot_file_name("sph", 0.5), "sph_t0.500.csv");
  EXPECT_EQ(snapshot_file_name("fem", 0), "fem_t0.000.csv");
  EXPECT_EQ(snapshot_file_name("fem", 2.5), "fem_t2.500.csv");
  EXPECT_EQ(snapshot_file_name("sph", 0.1234), "sph_t0.123.csv");
}

TEST(Snapshots, EachTimeOnceAtTheFirstStepReachingIt)
{
  // unsorted with a duplicate; steps of 0.03 from 0
  SnapshotSchedule s({0.1, 0.0, 0.05, 0.1, 0.06}, 0.0, false);
  EXPECT_EQ(s.pending(), (std::vector<double>{0.0, 0.05, 0.06, 0.1}));
  EXPECT_EQ(s.due(0.0), std::vector<double>{0.0});
  EXPECT_TRUE(s.due(0.03).empty());
  EXPECT_EQ(s.due(0.06), (std::vector<double>{0.05, 0.06})); // two times within one step
  EXPECT_TRUE(s.due(0.06).empty());                           // never twice
  EXPECT_TRUE(s.due(0.09).empty());
  // round-off: 0.1 reached as 0.03 + 0.03 + 0.03 + 0.01 (0.09999999999999999)
  EXPECT_EQ(s.due(0.03 + 0.03 + 0.03 + 0.01), std::vector<double>{0.1});
  EXPECT_TRUE(s.pending().empty());
}

TEST(Snapshots, RestartSkipsTimesAlreadyWritten)
{
  // restarted at t0 = 0.05: 0 and 0.05 were written by the run it continues, 0.07 was not
  SnapshotSchedule restarted({0.0, 0.05, 0.07}, 0.05, true);
  EXPECT_EQ(restarted.pending(), std::vector<double>{0.07});
  EXPECT_TRUE(restarted.due(0.06).empty());
  EXPECT_EQ(restarted.due(0.08), std::vector<double>{0.07});
  // a fresh run that starts at t0 writes them all
  SnapshotSchedule fresh({0.0, 0.05}, 0.0, false);
  EXPECT_EQ(fresh.due(0.0), std::vector<double>{0.0});
}
