// Session leases of a fleet on a real PostgreSQL server (started by the ctest fixture on loopback):
// a lease is held by one node at a time, passes on only once it expires, and fences the writes of
// the node that lost it.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "cluster/cluster_coordinator.hpp"
#include "cluster/cluster_repository.hpp"
#include "server/support/test_services.hpp"
#include "storage/database.hpp"
#include "storage/migrate.hpp"
#include "storage/session_repository.hpp"

namespace pslam::server {
namespace {

class ClusterLeaseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    Database db = Connect();
    ApplyMigrations(db, EmbeddedMigrations(StorageKind::kPostgres));
    SessionRow row;
    row.id = "s-1";
    row.source = "agent";
    row.status = "active";
    row.laser_json = row.settings_json = "{}";
    SessionRepository(db).CreateSession(row);
  }
  Database Connect() { return Database::Connect(postgres_.url()); }

  testing::TestPostgresDatabase postgres_;
};

TEST_F(ClusterLeaseTest, ALeaseIsHeldByOneNodeUntilItExpires) {
  Database a_db = Connect(), b_db = Connect();
  ClusterRepository a(a_db), b(b_db);
  EXPECT_EQ(a.Orphans(), std::vector<std::string>{"s-1"});
  const auto first = a.TryAcquire("s-1", "node-a", 1.0);
  ASSERT_TRUE(first.has_value());
  EXPECT_TRUE(a.Orphans().empty());
  EXPECT_FALSE(b.TryAcquire("s-1", "node-b", 1.0).has_value());  // held: refused
  EXPECT_EQ(a.TryAcquire("s-1", "node-a", 1.0), first);           // its owner's renewal keeps the epoch

  std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // no renewal: it expires
  EXPECT_EQ(b.Orphans(), std::vector<std::string>{"s-1"});
  const auto second = b.TryAcquire("s-1", "node-b", 5.0);
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(*second, *first + 1);
  EXPECT_FALSE(a.TryAcquire("s-1", "node-a", 1.0).has_value());
  EXPECT_TRUE(a.RenewLeases("node-a", 1.0).empty());  // the old owner finds it holds nothing
  EXPECT_EQ(b.RenewLeases("node-b", 5.0), std::vector<std::string>{"s-1"});
}

InputRecord Odometry(std::int64_t seq) {
  InputRecord in;
  in.seq = seq;
  in.kind = InputKind::kOdometry;
  return in;
}

TEST_F(ClusterLeaseTest, AWriteOfTheNodeThatLostTheLeaseIsRefused) {
  ClusterCoordinator::Hooks hooks;
  hooks.load = [] { return NodeLoad{}; };
  hooks.lost = [](const std::string&) {};
  hooks.adopt = [](const std::string&, std::int64_t) {};
  auto a = ClusterCoordinator::Start({"node-a", "127.0.0.1:1", 1.0}, postgres_.url(), hooks);
  ASSERT_TRUE(a) << a.error();
  auto& node_a = *a.value();
  node_a.Stop();  // no renewals from here on: its lease will expire

  Database db = Connect();
  SessionRepository repo(db);  // session s-1 is the fixture's
  const std::int64_t epoch = node_a.AcquireIn(db, "s-1");
  EXPECT_NO_THROW(node_a.CheckLeaseIn(db, "s-1", epoch));
  EXPECT_NO_THROW(node_a.InsertInputIn(repo, "s-1", epoch, Odometry(1)));

  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  Database b_db = Connect();
  ASSERT_TRUE(ClusterRepository(b_db).TryAcquire("s-1", "node-b", 5.0).has_value());
  try {
    node_a.CheckLeaseIn(db, "s-1", epoch);
    FAIL() << "node-a wrote after losing the lease";
  } catch (const StorageError& e) {
    EXPECT_NE(std::string(e.what()).find(kLeaseLost), std::string::npos) << e.what();
  }
  // An input's insert checks the lease itself: refused, and nothing stored.
  try {
    node_a.InsertInputIn(repo, "s-1", epoch, Odometry(2));
    FAIL() << "node-a stored an input after losing the lease";
  } catch (const StorageError& e) {
    EXPECT_NE(std::string(e.what()).find(kLeaseLost), std::string::npos) << e.what();
  }
  EXPECT_EQ(repo.LastInputSeq("s-1"), 1);
}

TEST_F(ClusterLeaseTest, AFencedWriteInProgressHoldsOffATakeoverUntilItCommits) {
  Database a_db = Connect(), b_db = Connect();
  ClusterRepository a(a_db), b(b_db);
  const auto epoch = a.TryAcquire("s-1", "node-a", 0.2);
  ASSERT_TRUE(epoch);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // expired, nobody took it yet
  Transaction write(a_db);
  ASSERT_TRUE(a.HoldsLease("s-1", "node-a", *epoch));  // still A's: A's write may go on
  std::atomic<bool> committed{false};
  bool taken = false, committed_first = false;
  std::thread takeover([&] {
    taken = b.TryAcquire("s-1", "node-b", 5.0).has_value();
    committed_first = committed.load();
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  committed = true;
  write.Commit();
  takeover.join();
  EXPECT_TRUE(taken);
  EXPECT_TRUE(committed_first) << "node-b took the session while node-a's write was in progress";
  EXPECT_FALSE(a.HoldsLease("s-1", "node-a", *epoch));
}

}  // namespace
}  // namespace pslam::server
