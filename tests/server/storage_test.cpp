// The storage contract, run against both engines: SQLite (a real file) and PostgreSQL (a real
// server on loopback, tests/server/support/test_services.hpp): migrations, the repository's
// round-trips, and the group-committing writer. Both must give the same answers.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>

#include "server/support/temp_dir.hpp"
#include "server/support/test_services.hpp"
#include "storage/migrate.hpp"
#include "storage/read_pool.hpp"
#include "storage/session_repository.hpp"
#include "storage/site_repository.hpp"
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

// A fresh, empty database of the engine under test.
class StorageContract : public ::testing::TestWithParam<StorageKind> {
 protected:
  void SetUp() override {
    if (GetParam() == StorageKind::kPostgres) {
      postgres_ = std::make_unique<testing::TestPostgresDatabase>();
      where_ = {StorageKind::kPostgres, postgres_->url()};
    } else {
      where_ = {StorageKind::kSqlite, (dir_.path() / "db.sqlite").string()};
    }
  }
  Database Open() { return Database::Open(where_, Database::Mode::kReadWrite); }
  Database OpenMigrated() {
    Database db = Open();
    ApplyMigrations(db, EmbeddedMigrations(GetParam()));
    return db;
  }
  const StorageLocation& where() const { return where_; }

 private:
  testing::TempDir dir_;
  std::unique_ptr<testing::TestPostgresDatabase> postgres_;
  StorageLocation where_;
};

INSTANTIATE_TEST_SUITE_P(Engines, StorageContract, ::testing::Values(StorageKind::kSqlite, StorageKind::kPostgres),
                         [](const auto& info) { return info.param == StorageKind::kSqlite ? "Sqlite" : "Postgres"; });

TEST(MigrationsTest, BothEnginesHaveTheSameVersionsAndNames) {
  const auto& sqlite = EmbeddedMigrations(StorageKind::kSqlite);
  const auto& postgres = EmbeddedMigrations(StorageKind::kPostgres);
  ASSERT_FALSE(sqlite.empty());
  ASSERT_EQ(sqlite.size(), postgres.size());
  for (std::size_t i = 0; i < sqlite.size(); ++i) {
    EXPECT_EQ(sqlite[i].version, postgres[i].version);
    EXPECT_EQ(sqlite[i].name, postgres[i].name);
    EXPECT_NE(sqlite[i].sql, postgres[i].sql);  // each in its engine's dialect
  }
}

TEST_P(StorageContract, MigrationsApplyOnceAndRecordTheVersion) {
  Database db = Open();
  const int version = ApplyMigrations(db, EmbeddedMigrations(GetParam()));
  EXPECT_EQ(version, static_cast<int>(EmbeddedMigrations(GetParam()).size()));
  EXPECT_EQ(SchemaVersion(db), version);
  EXPECT_EQ(ApplyMigrations(db, EmbeddedMigrations(GetParam())), version);  // idempotent
}

TEST_P(StorageContract, MigrationsRefuseADatabaseNewerThanTheServer) {
  Database db = Open();
  db.engine().SetSchemaVersion(999);
  EXPECT_THROW(ApplyMigrations(db, EmbeddedMigrations(GetParam())), std::runtime_error);
}

TEST_P(StorageContract, AFailingMigrationLeavesThePreviousVersion) {
  Database db = Open();
  std::vector<Migration> migrations = {{1, "0001_a.sql", "CREATE TABLE a (x INTEGER);"},
                                       {2, "0002_b.sql", "CREATE TABLE b (x INTEGER); THIS IS NOT SQL;"}};
  EXPECT_THROW(ApplyMigrations(db, migrations), StorageError);
  EXPECT_EQ(SchemaVersion(db), 1);
}

TEST_P(StorageContract, InputsAreStoredOnceAndLoadInOrder) {
  Database db = OpenMigrated();
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

TEST_P(StorageContract, FiltersTreatMetacharactersAsText) {
  Database db = OpenMigrated();
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

TEST_P(StorageContract, HypothesesRoundTripWithHistoryAndFilters) {
  Database db = OpenMigrated();
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

TEST_P(StorageContract, CheckpointsSessionsAndEventsRoundTripExactly) {
  Database db = OpenMigrated();
  SessionRepository repo(db);
  SessionRow row = NewSession("s-1", "lab", 1700000000.123456789);
  row.replay_of = "intel";
  repo.CreateSession(row);
  Checkpoint c;
  c.session_id = "s-1";
  c.processed_seq = 12;
  c.scans = 5;
  c.stats_json = R"({"scans":5})";
  c.tiles = {{0, 0, 64, 1, {1, 2, 3}}, {-1, 2, 64, 1, {}}};
  c.trajectory = {{0, 2, 0.1, "0.100000", 1.0 / 3.0, -2.5, 3.0}, {1, 4, 0.2, "", 1e-300, 0.0, -0.0}};
  repo.WriteCheckpoint(c, 10.0);
  c.tiles = {{0, 0, 64, 2, {9}}};  // a changed tile replaces the stored one
  c.trajectory = {{1, 4, 0.2, "", 7.0, 7.0, 7.0}};
  repo.WriteCheckpoint(c, 11.0);

  const auto tiles = repo.LoadTiles("s-1");
  ASSERT_EQ(tiles.size(), 2u);
  EXPECT_EQ(tiles[1].tx, -1);  // ordered by ty, tx
  EXPECT_TRUE(tiles[1].data.empty());
  EXPECT_EQ(repo.LoadTile("s-1", 0, 0)->data, std::vector<std::uint8_t>{9});
  EXPECT_EQ(repo.LoadTile("s-1", 0, 0)->revision, 2);
  EXPECT_FALSE(repo.LoadTile("s-1", 5, 5));
  const auto trajectory = repo.LoadTrajectory("s-1", 0, 10);
  ASSERT_EQ(trajectory.size(), 2u);
  EXPECT_EQ(trajectory[0].x, 1.0 / 3.0);  // bit for bit
  EXPECT_EQ(trajectory[0].stamp, "0.100000");
  EXPECT_EQ(trajectory[1].x, 7.0);
  EXPECT_EQ(trajectory[1].stamp, "");

  auto stored = repo.GetSession("s-1");
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->created_at, 1700000000.123456789);
  EXPECT_EQ(stored->replay_of, "intel");
  EXPECT_EQ(stored->processed_seq, 12);
  EXPECT_EQ(stored->stats_json, R"({"scans":5})");
  EXPECT_FALSE(stored->closed_at);
  repo.SetFailed("s-1", "it's broken; \"quoted\"", 20.0);
  repo.SetRebuilds("s-1", 3, 40);
  stored = repo.GetSession("s-1");
  EXPECT_EQ(stored->status, "failed");
  EXPECT_EQ(stored->closed_at, 20.0);
  EXPECT_EQ(stored->failure, "it's broken; \"quoted\"");
  EXPECT_EQ(stored->rebuilds, 3);
  EXPECT_EQ(repo.SessionIdsWithStatus("failed"), std::vector<std::string>{"s-1"});
  repo.SetStatus("s-1", "active", 21.0);
  EXPECT_FALSE(repo.GetSession("s-1")->closed_at);

  repo.AddEvent("s-1", "opened", "{}", 1.0);
  repo.AddEvent(std::nullopt, "refused", R"({"status":401})", 2.0);
  repo.AddEvent("s-1", "closed", "{}", 3.0);
  const auto events = repo.ListEvents("s-1", 10, 0);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, "closed");  // newest first
  ASSERT_EQ(repo.ListEvents(std::nullopt, 10, 0).size(), 1u);
  EXPECT_EQ(repo.ListEvents(std::nullopt, 10, 0)[0].detail_json, R"({"status":401})");

  EXPECT_TRUE(repo.DeleteSession("s-1"));
  EXPECT_FALSE(repo.DeleteSession("s-1"));
  EXPECT_FALSE(repo.GetSession("s-1"));
  EXPECT_TRUE(repo.LoadTiles("s-1").empty());  // cascaded
  EXPECT_TRUE(repo.ListEvents("s-1", 10, 0).empty());
}

TEST_P(StorageContract, SiteMapVersionsKeepTheirFilesByteForByte) {
  Database db = OpenMigrated();
  SiteRepository sites(db);
  sites.CreateSite({"site-1", "first floor", 5.0});
  SiteMapRow map;
  map.site_id = "site-1";
  map.resolution = 0.05;
  map.width = 2;
  map.height = 1;
  map.yaml = "image: map.pgm\nresolution: 0.05\n";
  map.pgm = std::string("P5\n2 1\n255\n\0\xff", 13);  // a NUL byte and a 255 inside
  EXPECT_EQ(sites.AddMapVersion(map), 1);
  map.source = "session";
  map.session_id = "s-9";
  EXPECT_EQ(sites.AddMapVersion(map), 2);
  const auto listed = sites.ListSites(10, 0);
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_EQ(listed[0].versions, 2);
  EXPECT_EQ(listed[0].latest_version, 2);
  const auto versions = sites.ListMapVersions("site-1");
  ASSERT_EQ(versions.size(), 2u);
  EXPECT_EQ(versions[0].version, 2);  // newest first
  EXPECT_TRUE(versions[0].pgm.empty());
  const auto first = sites.GetMapVersion("site-1", 1);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->pgm, map.pgm);
  EXPECT_EQ(first->yaml, map.yaml);
  EXPECT_FALSE(first->session_id);
  EXPECT_EQ(sites.GetMapVersion("site-1", 0)->session_id, "s-9");  // 0: the latest
  EXPECT_FALSE(sites.GetMapVersion("site-1", 3));
  EXPECT_FALSE(sites.GetSite("site-2"));
}

TEST_P(StorageContract, WriterCommitsBeforeCallingBackAndIsolatesFailingJobs) {
  auto writer = StorageWriter::Open(where());
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
  ReadPool pool(where());
  EXPECT_EQ(pool.Acquire()->repository().LastInputSeq("s-1"), 50);
  EXPECT_EQ(pool.Acquire()->repository().LoadInputs("s-1", 0, 100).size(), 49u);
  writer.value()->Stop();
}

}  // namespace
}  // namespace pslam::server
