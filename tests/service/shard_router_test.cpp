// One daemon's view of a shard group (ShardRouter), with several routers standing for the
// daemons: each vehicle has exactly one owner among them, a leaver's flying vehicles are resumed
// from their last revision and its unplanned ones planned, a joiner takes only requests that
// arrive after it, a fleet has one owner for all its vehicles, and a cancelled mission is never
// planned again by the next owner. A shard restarted on its journal gets its copies back without
// planning them, and the members agree which requests it read (its earlier lives, not its gap).
// A shard that stood still begins a new life: it lets go of everything and takes back none of its
// old vehicles; another daemon's revision of its own plan reveals a takeover and fences it.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "service/shard_assignment.hpp"
#include "service/shard_router.hpp"

namespace skyroute {
namespace {

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kMargin = kSecond;

MissionRequestData mission(const std::string& vehicle, const std::string& request) {
  MissionRequestData m;
  m.vehicle_id = vehicle;
  m.request_id = request;
  return m;
}

TrajectoryData published(const MissionRequestData& m, std::uint32_t revision, std::int64_t start_ns,
                         std::int64_t end_ns) {
  TrajectoryData t;
  t.vehicle_id = m.vehicle_id;
  t.request_id = m.request_id;
  t.plan_id = m.vehicle_id + "-7";
  t.revision = revision;
  TrajectorySampleData first;
  first.t_rel_s = 0.0;
  first.utc_ns = start_ns;
  TrajectorySampleData last = first;
  last.t_rel_s = static_cast<double>(end_ns - start_ns) * 1e-9;
  last.utc_ns = end_ns;
  t.samples = {first, last};
  return t;
}

// Three daemons started at t = 0, 0 and 0; requests from t = 10 s.
struct Group {
  std::vector<ShardMember> members{{"shard-a", 0}, {"shard-b", 0}, {"shard-c", 0}};
  std::map<std::string, std::unique_ptr<ShardRouter>> routers;
  Group() {
    for (const ShardMember& m : members) {
      routers[m.service_id] = std::make_unique<ShardRouter>(m, kMargin);
      routers[m.service_id]->setMembers(members, true, 5 * kSecond);
    }
  }
  std::vector<std::string> ownersOf(const std::string& vehicle) const {
    std::vector<std::string> out;
    for (const auto& [id, r] : routers)
      if (r->ownsVehicle(vehicle)) out.push_back(id);
    return out;
  }
};

TEST(ShardRouter, EachVehicleHasExactlyOneOwnerWhoAloneIsToldToPlanIt) {
  Group g;
  for (int i = 0; i < 60; ++i) {
    const MissionRequestData m = mission("uav-" + std::to_string(i), "r" + std::to_string(i));
    int planners = 0;
    for (auto& [id, r] : g.routers) {
      const ShardActions a = r->onMission(m, 10 * kSecond);
      planners += static_cast<int>(a.plan.size());
    }
    EXPECT_EQ(planners, 1) << m.vehicle_id;
    ASSERT_EQ(g.ownersOf(m.vehicle_id).size(), 1u) << m.vehicle_id;
  }
  for (auto& [id, r] : g.routers) EXPECT_GT(r->ownedVehicles(), 5u) << id;
}

TEST(ShardRouter, NothingIsOwnedBeforeTheDaemonSettles) {
  ShardRouter alone({"shard-a", 0}, kMargin);
  EXPECT_TRUE(alone.onMission(mission("uav-1", "r1"), 10 * kSecond).plan.empty());
  EXPECT_FALSE(alone.ownsVehicle("uav-1"));
  const ShardActions settled = alone.setMembers({}, true, 11 * kSecond);
  ASSERT_EQ(settled.plan.size(), 1u) << "a single daemon plans everything once settled";
  EXPECT_EQ(settled.plan[0].request_id, "r1");
  EXPECT_TRUE(alone.ownsVehicle("uav-1"));
}

TEST(ShardRouter, ALeaversFlyingVehiclesAreResumedAndItsUnplannedOnesPlanned) {
  Group g;
  std::vector<MissionRequestData> missions;
  for (int i = 0; i < 30; ++i) missions.push_back(mission("uav-" + std::to_string(i), "r" + std::to_string(i)));
  for (const MissionRequestData& m : missions)
    for (auto& [id, r] : g.routers) r->onMission(m, 10 * kSecond);
  std::map<std::string, std::string> owner;
  for (const MissionRequestData& m : missions) owner[m.vehicle_id] = g.ownersOf(m.vehicle_id).at(0);
  // Every vehicle of shard-b flies (revision 4) except the first, still being planned.
  bool first_of_b = true;
  std::vector<std::string> b_flying, b_planning;
  for (const MissionRequestData& m : missions) {
    if (owner[m.vehicle_id] == "shard-b" && first_of_b) {
      first_of_b = false;
      b_planning.push_back(m.vehicle_id);
      continue;
    }
    if (owner[m.vehicle_id] == "shard-b") b_flying.push_back(m.vehicle_id);
    const TrajectoryData t = published(m, 4, 10 * kSecond, 500 * kSecond);
    for (auto& [id, r] : g.routers) r->onTrajectory(t);
  }
  ASSERT_FALSE(b_flying.empty());
  g.routers.erase("shard-b");
  const std::vector<ShardMember> left{{"shard-a", 0}, {"shard-c", 0}};
  std::map<std::string, int> resumed, planned;
  for (auto& [id, r] : g.routers) {
    const ShardActions a = r->setMembers(left, true, 20 * kSecond);
    EXPECT_TRUE(a.release_vehicles.empty()) << id << " let go of a vehicle though its owner stayed";
    for (const auto& [m, last] : a.resume) {
      ++resumed[m.vehicle_id];
      EXPECT_EQ(last.identity.revision, 4u);
      EXPECT_EQ(last.identity.plan_id, m.vehicle_id + "-7");
      EXPECT_EQ(last.flight_start_utc_ns, 10 * kSecond);
    }
    for (const MissionRequestData& m : a.plan) ++planned[m.vehicle_id];
  }
  for (const std::string& v : b_flying) EXPECT_EQ(resumed[v], 1) << v;
  for (const std::string& v : b_planning) EXPECT_EQ(planned[v], 1) << v;
  EXPECT_EQ(resumed.size() + planned.size(), b_flying.size() + b_planning.size()) << "only shard-b's vehicles move";
  for (const MissionRequestData& m : missions) {
    const auto owners = g.ownersOf(m.vehicle_id);
    ASSERT_EQ(owners.size(), 1u);
    if (owner[m.vehicle_id] != "shard-b") {
      EXPECT_EQ(owners[0], owner[m.vehicle_id]);
    }
  }
}

TEST(ShardRouter, AJoinerTakesOnlyRequestsThatArriveAfterItsMargin) {
  Group g;
  for (int i = 0; i < 30; ++i)
    for (auto& [id, r] : g.routers) r->onMission(mission("old-" + std::to_string(i), "o"), 10 * kSecond);
  std::map<std::string, std::string> owner;
  for (int i = 0; i < 30; ++i) owner["old-" + std::to_string(i)] = g.ownersOf("old-" + std::to_string(i)).at(0);
  // shard-d starts at 20 s; it never saw the old requests.
  const ShardMember d{"shard-d", 20 * kSecond};
  g.members.push_back(d);
  g.routers["shard-d"] = std::make_unique<ShardRouter>(d, kMargin);
  for (auto& [id, r] : g.routers) {
    const ShardActions a = r->setMembers(g.members, true, 21 * kSecond);
    EXPECT_TRUE(a.release_vehicles.empty() && a.plan.empty() && a.resume.empty()) << id;
  }
  for (int i = 0; i < 30; ++i) EXPECT_EQ(g.ownersOf("old-" + std::to_string(i)), std::vector<std::string>{owner["old-" + std::to_string(i)]});
  int by_d = 0;
  for (int i = 0; i < 40; ++i) {
    const MissionRequestData m = mission("new-" + std::to_string(i), "n");
    for (auto& [id, r] : g.routers) r->onMission(m, 22 * kSecond);
    const auto owners = g.ownersOf(m.vehicle_id);
    ASSERT_EQ(owners.size(), 1u);
    by_d += owners[0] == "shard-d";
  }
  EXPECT_GT(by_d, 3);
  // A cancel naming an old vehicle the joiner never heard of, or a vehicle nobody has: one answer.
  for (const std::string& vehicle : {std::string("old-3"), std::string("nobody")}) {
    CancelRequestData cancel;
    cancel.vehicle_id = vehicle;
    int answering = 0;
    for (auto& [id, r] : g.routers) answering += r->onCancel(cancel) ? 1 : 0;
    EXPECT_EQ(answering, 1) << vehicle;
  }
}

TEST(ShardRouter, AFleetHasOneOwnerForAllItsVehiclesAndACancelledMissionIsNotPlannedAgain) {
  Group g;
  FleetRequestData fleet;
  fleet.request_id = "fleet-1";
  fleet.vehicle_ids = {"f-1", "f-2", "f-3", "f-4", "f-5"};
  int fleet_planners = 0;
  for (auto& [id, r] : g.routers) fleet_planners += static_cast<int>(r->onFleet(fleet, 10 * kSecond).plan_fleets.size());
  EXPECT_EQ(fleet_planners, 1);
  const std::string fleet_owner = rendezvousOwner({"shard-a", "shard-b", "shard-c"}, "fleet:fleet-1");
  for (const std::string& v : fleet.vehicle_ids) EXPECT_EQ(g.ownersOf(v), std::vector<std::string>{fleet_owner});
  for (auto& [id, r] : g.routers) EXPECT_EQ(r->ownsFleet("fleet-1"), id == fleet_owner);

  // A cancelled mission whose owner then leaves: nobody plans it again, and one daemon answered the cancel.
  const MissionRequestData m = mission("c-1", "rc");
  for (auto& [id, r] : g.routers) r->onMission(m, 10 * kSecond);
  const std::string owner = g.ownersOf("c-1").at(0);
  CancelRequestData cancel;
  cancel.request_id = "rc";  // by request id alone
  int answering = 0;
  for (auto& [id, r] : g.routers) answering += r->onCancel(cancel) ? 1 : 0;
  EXPECT_EQ(answering, 1);
  g.routers.erase(owner);
  std::vector<ShardMember> left;
  for (const ShardMember& member : g.members)
    if (member.service_id != owner) left.push_back(member);
  for (auto& [id, r] : g.routers) {
    const ShardActions a = r->setMembers(left, true, 20 * kSecond);
    for (const MissionRequestData& p : a.plan) EXPECT_NE(p.vehicle_id, "c-1");
    EXPECT_TRUE(a.resume.empty());
  }
}

TEST(ShardCoverage, ARequestIsCoveredByTheLifeItArrivedInNotByTheGaps) {
  const std::vector<CoverageInterval> past{{0, 30 * kSecond}, {40 * kSecond, 60 * kSecond}};
  const auto covered = [&](std::int64_t t) { return coversArrival(100 * kSecond, past, t, kMargin); };
  EXPECT_FALSE(covered(kSecond / 2)) << "within the first life's join margin";
  EXPECT_TRUE(covered(10 * kSecond));
  EXPECT_TRUE(covered(30 * kSecond));
  EXPECT_FALSE(covered(35 * kSecond)) << "down between its lives";
  EXPECT_FALSE(covered(40 * kSecond + kMargin / 2));
  EXPECT_TRUE(covered(50 * kSecond));
  EXPECT_FALSE(covered(80 * kSecond));
  EXPECT_FALSE(covered(100 * kSecond));
  EXPECT_TRUE(covered(101 * kSecond)) << "the current life, a margin after its start";
  EXPECT_FALSE(coversArrival(100 * kSecond, {}, 10 * kSecond, kMargin)) << "no journal: only the current life";

  // Advertised: lives that cover something, the newest kMaxPastCoverage, oldest first; as text and back.
  std::vector<CoverageInterval> lives;
  for (std::int64_t i = 7; i >= 1; --i) lives.push_back({i * 100 * kSecond, i * 100 * kSecond + 50 * kSecond});
  lives.push_back({800 * kSecond, 800 * kSecond + kMargin / 2});  // killed before it covered anything
  const std::vector<CoverageInterval> advertised = advertisedCoverage(lives, kMargin);
  ASSERT_EQ(advertised.size(), kMaxPastCoverage);
  EXPECT_EQ(advertised.front().started_utc_ns, 400 * kSecond);
  EXPECT_EQ(advertised.back().started_utc_ns, 700 * kSecond);
  EXPECT_EQ(coverageFromText(coverageText(advertised)), advertised);
  EXPECT_LE(coverageText(advertised).size(), 4u * 40u) << "USER_DATA stays small";
  EXPECT_EQ(coverageFromText(""), std::vector<CoverageInterval>{});
  for (const char* bad : {"1", "1-", "-2", "1-2,", "a-2", "1-2,3-4,5-6,7-8,9-10"}) {
    EXPECT_FALSE(coverageFromText(bad)) << bad;
  }
}

// A shard that plans nothing until settled, recovering copies a journal kept.
TEST(ShardRouter, ARestartedShardsCopiesComeBackUnplannedAndItTakesItsVehiclesWhenTheirOwnerDies) {
  Group g;
  std::vector<JournaledRequest> journal_of_c;  // what shard-c journals as it reads
  std::vector<MissionRequestData> old_missions, gap_missions;
  for (int i = 0; i < 60; ++i) old_missions.push_back(mission("old-" + std::to_string(i), "o" + std::to_string(i)));
  for (int i = 0; i < 20; ++i) gap_missions.push_back(mission("gap-" + std::to_string(i), "g" + std::to_string(i)));
  for (const MissionRequestData& m : old_missions) {
    for (auto& [id, r] : g.routers) r->onMission(m, 10 * kSecond);
    journal_of_c.push_back(JournaledRequest{ShardRouter::missionKey(m.vehicle_id), 10 * kSecond, m, std::nullopt});
    for (auto& [id, r] : g.routers) r->onTrajectory(published(m, 2, 10 * kSecond, 500 * kSecond));
  }
  std::map<std::string, std::string> first_owner;
  for (const MissionRequestData& m : old_missions) first_owner[m.vehicle_id] = g.ownersOf(m.vehicle_id).at(0);

  // shard-c dies at 30 s (its journal covered up to 29 s); requests arrive while it is down.
  g.routers.erase("shard-c");
  const std::vector<ShardMember> ab{{"shard-a", 0}, {"shard-b", 0}};
  for (auto& [id, r] : g.routers) r->setMembers(ab, true, 31 * kSecond);
  for (const MissionRequestData& m : gap_missions) {
    for (auto& [id, r] : g.routers) r->onMission(m, 40 * kSecond);
    for (auto& [id, r] : g.routers) r->onTrajectory(published(m, 0, 40 * kSecond, 500 * kSecond));
  }

  // Restarted at 50 s on its journal: its copies come back, nothing is planned before it settles.
  const ShardMember c{"shard-c", 50 * kSecond, {{0, 29 * kSecond}}};
  auto restarted = std::make_unique<ShardRouter>(c, kMargin);
  restarted->recoverRequests(journal_of_c);
  EXPECT_EQ(restarted->ownedVehicles(), 0u);
  for (const MissionRequestData& m : old_missions) EXPECT_FALSE(restarted->ownsVehicle(m.vehicle_id));
  for (const MissionRequestData& m : old_missions) restarted->onTrajectory(published(m, 2, 10 * kSecond, 500 * kSecond));
  for (const MissionRequestData& m : gap_missions) restarted->onTrajectory(published(m, 0, 40 * kSecond, 500 * kSecond));
  g.routers["shard-c"] = std::move(restarted);
  const std::vector<ShardMember> abc{{"shard-a", 0}, {"shard-b", 0}, c};
  std::map<std::string, int> resumed_by_c;
  for (auto& [id, r] : g.routers) {
    const ShardActions a = r->setMembers(abc, true, 52 * kSecond);
    if (id != "shard-c") continue;
    EXPECT_TRUE(a.plan.empty()) << "flying vehicles are resumed from the wire, never planned from scratch";
    for (const auto& [m, last] : a.resume) {
      ++resumed_by_c[m.vehicle_id];
      EXPECT_EQ(last.identity.revision, 2u);
    }
  }
  // Every member agrees: shard-c takes back exactly the old vehicles it ranks first for, and none
  // of those that arrived while it was down.
  for (const MissionRequestData& m : old_missions) {
    ASSERT_EQ(g.ownersOf(m.vehicle_id).size(), 1u) << m.vehicle_id;
    EXPECT_EQ(g.ownersOf(m.vehicle_id)[0], first_owner[m.vehicle_id]) << m.vehicle_id;
    EXPECT_EQ(resumed_by_c.count(m.vehicle_id), first_owner[m.vehicle_id] == "shard-c" ? 1u : 0u) << m.vehicle_id;
  }
  for (const MissionRequestData& m : gap_missions) {
    ASSERT_EQ(g.ownersOf(m.vehicle_id).size(), 1u) << m.vehicle_id;
    EXPECT_NE(g.ownersOf(m.vehicle_id)[0], "shard-c") << m.vehicle_id << " arrived while shard-c was down";
  }

  // shard-a dies: its old vehicles for which shard-c ranks above shard-b go to shard-c, resumed.
  std::vector<std::string> to_c, to_b_gap;
  for (const MissionRequestData& m : old_missions) {
    if (first_owner[m.vehicle_id] == "shard-a" && rendezvousOwner({"shard-b", "shard-c"}, "vehicle:" + m.vehicle_id) == "shard-c") {
      to_c.push_back(m.vehicle_id);
    }
  }
  for (const MissionRequestData& m : gap_missions) {
    if (g.ownersOf(m.vehicle_id)[0] == "shard-a") to_b_gap.push_back(m.vehicle_id);
  }
  ASSERT_FALSE(to_c.empty());
  ASSERT_FALSE(to_b_gap.empty());
  g.routers.erase("shard-a");
  const std::vector<ShardMember> bc{{"shard-b", 0}, c};
  std::map<std::string, int> resumed_after;
  for (auto& [id, r] : g.routers) {
    const ShardActions a = r->setMembers(bc, true, 60 * kSecond);
    for (const auto& [m, last] : a.resume) resumed_after[id + ":" + m.vehicle_id]++;
    EXPECT_TRUE(a.plan.empty()) << id;
  }
  for (const std::string& v : to_c) {
    EXPECT_EQ(g.ownersOf(v), std::vector<std::string>{"shard-c"}) << v;
    EXPECT_EQ(resumed_after["shard-c:" + v], 1) << v;
  }
  for (const std::string& v : to_b_gap) {
    EXPECT_EQ(g.ownersOf(v), std::vector<std::string>{"shard-b"}) << v << ": shard-c never read it";
    EXPECT_EQ(resumed_after["shard-b:" + v], 1) << v;
  }
}

TEST(ShardRouter, AFleetReplacedForAllItsVehiclesIsForgotten) {
  ShardRouter alone({"shard-a", 0}, kMargin);
  FleetRequestData fleet;
  fleet.request_id = "fleet-1";
  fleet.vehicle_ids = {"f-1", "f-2"};
  EXPECT_TRUE(alone.onFleet(fleet, 10 * kSecond).forget_requests.empty());
  EXPECT_TRUE(alone.onMission(mission("f-1", "m1"), 11 * kSecond).forget_requests.empty()) << "f-2 still flies it";
  EXPECT_EQ(alone.onMission(mission("f-2", "m2"), 12 * kSecond).forget_requests,
            std::vector<std::string>{ShardRouter::fleetKey("fleet-1")});
}


// A shard that stood still past its lease (docs/dds.md "A paused shard"): its peers took its
// vehicles over. Beginning a new life it lets go of every vehicle it had, owns nothing until it
// settles again, and then, a joiner as of the new life, takes back none of the old vehicles
// while a member that read their requests is live; it takes new requests as any member does.
TEST(ShardRouter, ANewLifeReleasesEveryVehicleAndTakesBackNoneOfThemWhileTheirReadersLive) {
  Group g;
  std::vector<MissionRequestData> missions;
  for (int i = 0; i < 30; ++i) missions.push_back(mission("uav-" + std::to_string(i), "r" + std::to_string(i)));
  for (const MissionRequestData& m : missions)
    for (auto& [id, r] : g.routers) r->onMission(m, 10 * kSecond);
  std::vector<std::string> of_b;
  for (const MissionRequestData& m : missions)
    if (g.ownersOf(m.vehicle_id) == std::vector<std::string>{"shard-b"}) of_b.push_back(m.vehicle_id);
  ASSERT_FALSE(of_b.empty());

  // shard-b stood still from 20 s to 23 s; the others saw it go and took its vehicles.
  const std::vector<ShardMember> without_b{{"shard-a", 0}, {"shard-c", 0}};
  for (const char* id : {"shard-a", "shard-c"}) g.routers[id]->setMembers(without_b, true, 21 * kSecond);
  ShardRouter& b = *g.routers["shard-b"];
  const ShardActions released = b.beginLife(23 * kSecond, 23 * kSecond);
  EXPECT_EQ(released.release_vehicles.size(), of_b.size());
  EXPECT_TRUE(released.plan.empty() && released.resume.empty());
  EXPECT_EQ(b.lifeStartedUtcNs(), 23 * kSecond);
  EXPECT_EQ(b.ownedVehicles(), 0u);
  for (const std::string& v : of_b) EXPECT_FALSE(b.ownsVehicle(v)) << v;

  // Back with its new life, as the others see it in its heartbeats; it has listened and settles.
  const std::vector<ShardMember> again{{"shard-a", 0}, {"shard-b", 23 * kSecond}, {"shard-c", 0}};
  for (auto& [id, r] : g.routers) {
    const ShardActions a = r->setMembers(again, true, 25 * kSecond);
    EXPECT_TRUE(a.release_vehicles.empty() && a.plan.empty() && a.resume.empty()) << id << " moved a vehicle";
  }
  for (const MissionRequestData& m : missions) {
    const auto owners = g.ownersOf(m.vehicle_id);
    ASSERT_EQ(owners.size(), 1u) << m.vehicle_id;
    EXPECT_NE(owners[0], "shard-b") << m.vehicle_id << " went back to the shard that stood still";
  }
  // It takes new requests as any member does.
  int by_b = 0;
  for (int i = 0; i < 40; ++i) {
    const MissionRequestData m = mission("new-" + std::to_string(i), "n" + std::to_string(i));
    for (auto& [id, r] : g.routers) r->onMission(m, 30 * kSecond);
    const auto owners = g.ownersOf(m.vehicle_id);
    ASSERT_EQ(owners.size(), 1u);
    by_b += owners[0] == "shard-b";
  }
  EXPECT_GT(by_b, 3);
}

// The trajectories on the wire fence a shard: another daemon's revision of the plan it last wrote
// for a vehicle it owns says it was taken for dead; and a revision it is about to write that
// another daemon already wrote (or overtook) is superseded.
TEST(ShardRouter, AnotherDaemonsRevisionOfOurPlanRevealsATakeoverAndSupersedesOurs) {
  const std::vector<ShardMember> members{{"shard-a", 0}, {"shard-b", 0}};
  ShardRouter a(members[0], kMargin, "instance-a");
  a.setMembers(members, true, 5 * kSecond);
  std::string mine;
  for (int i = 0; i < 20 && mine.empty(); ++i) {
    const MissionRequestData m = mission("uav-" + std::to_string(i), "r" + std::to_string(i));
    a.onMission(m, 10 * kSecond);
    if (a.ownsVehicle(m.vehicle_id)) mine = m.vehicle_id;
  }
  ASSERT_FALSE(mine.empty());
  const MissionRequestData m = mission(mine, "r");
  TrajectoryData ours = published(m, 4, 10 * kSecond, 500 * kSecond);
  a.onPublished(ours);

  TrajectoryData theirs = ours;
  theirs.source_instance = "instance-b";
  theirs.revision = 5;
  TrajectoryData other_plan = theirs;
  other_plan.plan_id = mine + "-other";
  TrajectoryData older = theirs;
  older.revision = 3;
  EXPECT_FALSE(a.onTrajectory(older)) << "an older revision reveals nothing";
  EXPECT_FALSE(a.onTrajectory(other_plan)) << "another plan is a new request's, not a takeover";
  a.onPublished(ours);  // ours again in force on the wire
  EXPECT_TRUE(a.onTrajectory(theirs));

  // Our next revision 5 stands for another trajectory than theirs: superseded; 6 is not.
  TrajectoryData next = ours;
  next.revision = 5;
  EXPECT_TRUE(a.supersededOnWire(next));
  next.revision = 6;
  EXPECT_FALSE(a.supersededOnWire(next));
  // Our own revisions never supersede ours.
  a.onPublished(next);
  next.revision = 6;
  EXPECT_FALSE(a.supersededOnWire(next));
  // A vehicle this shard does not own: another daemon's revisions are no takeover.
  ShardRouter b(members[1], kMargin, "instance-b");
  b.setMembers(members, true, 5 * kSecond);
  b.onMission(m, 10 * kSecond);
  ASSERT_FALSE(b.ownsVehicle(mine));
  TrajectoryData from_a = ours;
  from_a.source_instance = "instance-a";
  EXPECT_FALSE(b.onTrajectory(from_a));
}

}  // namespace
}  // namespace skyroute
