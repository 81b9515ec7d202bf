// Storage: migrations, the repository's round-trips, and the group-committing writer.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "server/support/temp_dir.hpp"
#include "storage/migrate.hpp"
#include "storage/read_pool.hpp"
#include "storage/session_repository.hpp"
#include "storage/storage_writer.hpp"

namespace pslam::server {
namespace {

SessionRow NewSession(const std::string& id, const std::string& name, double created) {
  SessionRow row;
  row.id = id;
  row.name = name;
  row.robot_id = "r1";
  row.created_at = row.updated_at = created;
  return row;
}

TEST(MigrateTest, AppliesOnceAndRecordsUserVersion) {
  testing::TempDir dir;
  Database db = Database::Open(dir.path() / "db.sqlite", Database::Mode::kReadWrite);
  const int version = ApplyMigrations(db, EmbeddedMigrations());
  EXPECT_EQ(version, static_cast<int>(EmbeddedMigrations().size()));
  EXPECT_EQ(SchemaVersion(db), version);
  EXPECT_EQ(ApplyMigrations(db, EmbeddedMigrations()), version);  // idempotent
}

TEST(MigrateTest, RefusesADatabaseNewerThanTheServer) {
  testing::TempDir dir;
  Database db = Database::Open(dir.path() / "db.sqlite", Database::Mode::kReadWrite);
  db.Exec("PRAGMA user_version = 999");
  EXPECT_THROW(ApplyMigrations(db, EmbeddedMigrations()), std::runtime_error);
}

TEST(MigrateTest, AFailingMigrationLeavesThePreviousVersion) {
  testing::TempDir dir;
  Database db = Database::Open(dir.path() / "db.sqlite", Database::Mode::kReadWrite);
  std::vector<Migration> migrations = {{1, "0001_a.sql", "CREATE TABLE a (x INTEGER);"},
                                       {2, "0002_b.sql", "CREATE TABLE b (x INTEGER); THIS IS NOT SQL;"}};
  EXPECT_THROW(ApplyMigrations(db, migrations), SqliteError);
  EXPECT_EQ(SchemaVersion(db), 1);
}

TEST(SessionRepositoryTest, InputsAreStoredOnceAndLoadInOrder) {
  testing::TempDir dir;
  Database db = Database::Open(dir.path() / "db.sqlite", Database::Mode::kReadWrite);
  ApplyMigrations(db, EmbeddedMigrations());
  SessionRepository repo(db);
  repo.CreateSession(NewSession("s-1", "one", 1.0));
  InputRecord scan;
  scan.seq = 2;
  scan.kind = InputKind::kScan;
  scan.t = 10.5;
  scan.ranges = {1.0f, std::numeric_limits<float>::quiet_NaN(), 3.5f};
  scan.stamp = "10.500000";
  InputRecord odom;
  odom.seq = 1;
  odom.kind = InputKind::kOdometry;
  odom.x = 0.5;
  odom.v = 0.2;
  repo.InsertInput("s-1", scan);
  repo.InsertInput("s-1", odom);
  scan.ranges = {9.0f};
  repo.InsertInput("s-1", scan);  // a resend: ignored, the first copy stays
  EXPECT_EQ(repo.LastInputSeq("s-1"), 2);
  const auto inputs = repo.LoadInputs("s-1", 0, 10);
  ASSERT_EQ(inputs.size(), 2u);
  EXPECT_EQ(inputs[0].kind, InputKind::kOdometry);
  EXPECT_DOUBLE_EQ(inputs[0].v, 0.2);
  ASSERT_EQ(inputs[1].ranges.size(), 3u);
  EXPECT_TRUE(std::isnan(inputs[1].ranges[1]));
  EXPECT_EQ(inputs[1].stamp, "10.500000");
  EXPECT_EQ(repo.LoadInputs("s-1", 1, 10).size(), 1u);
}

TEST(SessionRepositoryTest, FiltersTreatMetacharactersAsText) {
  testing::TempDir dir;
  Database db = Database::Open(dir.path() / "db.sqlite", Database::Mode::kReadWrite);
  ApplyMigrations(db, EmbeddedMigrations());
  SessionRepository repo(db);
  repo.CreateSession(NewSession("s-1", "lab 100%", 1.0));
  repo.CreateSession(NewSession("s-2", "office", 2.0));
  SessionFilter filter;
  filter.name_contains = "%";
  EXPECT_EQ(repo.ListSessions(filter).total, 1);
  filter.name_contains = "' OR 1=1 --";
  EXPECT_EQ(repo.ListSessions(filter).total, 0);
  filter.name_contains.reset();
  filter.status = "active'; DROP TABLE sessions; --";
  EXPECT_EQ(repo.ListSessions(filter).total, 0);
  EXPECT_EQ(repo.ListSessions({}).total, 2);
  SessionFilter page;
  page.limit = 1;
  page.offset = 1;
  const auto second = repo.ListSessions(page);
  ASSERT_EQ(second.sessions.size(), 1u);
  EXPECT_EQ(second.sessions[0].id, "s-1");  // newest first
}

TEST(SessionRepositoryTest, HypothesesRoundTripWithHistoryAndFilters) {
  testing::TempDir dir;
  Database db = Database::Open(dir.path() / "db.sqlite", Database::Mode::kReadWrite);
  ApplyMigrations(db, EmbeddedMigrations());
  SessionRepository repo(db);
  repo.CreateSession(NewSession("s-1", "one", 1.0));
  HypothesisRecord h;
  h.id = 7;
  h.time = 100.0;
  h.target_cell = {40, 20};
  h.reference_cell = {10, 20};
  h.theta = 0.5;
  h.translation_x = 1.5;
  h.psi = 0.8;
  h.area = 2.0;
  h.cells = {{40, 20, 0.9f}, {41, 21, 0.1f}};
  Checkpoint c;
  c.session_id = "s-1";
  c.resolution = 0.05;
  c.hypotheses = {h};
  repo.WriteCheckpoint(c, 5.0);
  h.status = "confirmed";
  h.hit_ratio = 0.75;
  c.hypotheses = {h};
  repo.WriteCheckpoint(c, 6.0);

  const auto stored = repo.GetHypothesis("s-1", 7);
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->status, "confirmed");
  ASSERT_EQ(stored->cells.size(), 2u);
  EXPECT_EQ(stored->cells[1].x, 41);
  EXPECT_FLOAT_EQ(stored->cells[0].occupancy, 0.9f);
  EXPECT_EQ(repo.HypothesisHistory("s-1", 7).size(), 2u);

  HypothesisFilter f;
  f.min_psi = 0.9;
  EXPECT_EQ(repo.QueryHypotheses("s-1", f).total, 0);
  f.min_psi = 0.5;
  f.bbox = std::array<double, 4>{1.9, 0.9, 2.1, 1.1};  // around cell (40, 20) at 5 cm
  EXPECT_EQ(repo.QueryHypotheses("s-1", f).total, 1);
  f.bbox = std::array<double, 4>{-5, -5, -4, -4};
  EXPECT_EQ(repo.QueryHypotheses("s-1", f).total, 0);
  const auto counts = repo.CountHypotheses("s-1");
  EXPECT_EQ(counts.accepted, 1);
  EXPECT_EQ(counts.confirmed, 1);
  EXPECT_EQ(counts.pending, 0);
  EXPECT_EQ(counts.refuted, 0);
}

TEST(StorageWriterTest, CommitsBeforeCallingBackAndIsolatesFailingJobs) {
  testing::TempDir dir;
  const std::string path = dir.path() / "db.sqlite";
  auto writer = StorageWriter::Open(path, true);
  ASSERT_TRUE(writer) << writer.error();
  writer.value()->Execute([](SessionRepository& repo) { repo.CreateSession(NewSession("s-1", "one", 1.0)); });
  std::atomic<int> ok{0}, failed{0};
  for (int seq = 1; seq <= 50; ++seq) {
    writer.value()->Submit(
        [seq](SessionRepository& repo) {
          InputRecord in;
          in.seq = seq;
          repo.InsertInput(seq == 25 ? "no-such-session" : "s-1", in);  // 25 violates the foreign key
        },
        [&](bool committed, const std::string&) { (committed ? ok : failed)++; });
  }
  writer.value()->Execute([](SessionRepository&) {});
  EXPECT_EQ(ok.load(), 49);
  EXPECT_EQ(failed.load(), 1);
  ReadPool pool(path);
  EXPECT_EQ(pool.Acquire()->repository().LastInputSeq("s-1"), 50);
  EXPECT_EQ(pool.Acquire()->repository().LoadInputs("s-1", 0, 100).size(), 49u);
  writer.value()->Stop();
}

}  // namespace
}  // namespace pslam::server
