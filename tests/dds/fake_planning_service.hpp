// A stand-in for the planning service in the request tool's tests: it reads MissionRequests,
// answers with PlanStatus, and announces itself with a ServiceStatus writer (the tool reaches every
// live service it knows from their heartbeat writers). Each listen() makes a fresh loop that the
// first request heard stops.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "service/dds/dds_entities.hpp"
#include "service/dds/service_instance.hpp"
#include "service/dds/typed_io.hpp"
#include "service/dds/wait_loop.hpp"

namespace skyroute::testing {

struct FakePlanningService {
  std::optional<dds::Entity> participant;
  std::optional<dds::Reader<MissionRequestData>> requests;
  std::optional<dds::Writer<PlanStatusData>> statuses;
  std::optional<dds::Writer<ServiceStatusData>> heartbeat;
  std::optional<dds::WaitLoop> loop;
  std::vector<MissionRequestData> heard;  // every request read, in order

  // A stopped loop does not run again: each round of a test listens anew.
  bool listen() {
    auto made = dds::WaitLoop::create(participant->get());
    if (!made.ok()) {
      ADD_FAILURE() << made.error().describe();
      return false;
    }
    loop.emplace(std::move(*made));
    return loop
        ->add<MissionRequestData>(
            *requests,
            [this](MissionRequestData&& m) {
              heard.push_back(std::move(m));
              loop->stop();
            },
            [](const Error& e) { ADD_FAILURE() << e.describe(); })
        .ok();
  }
};

// Null, with a test failure, when an entity cannot be made. Heap-held: the loop's callback keeps
// a pointer to it.
inline std::unique_ptr<FakePlanningService> startFakePlanningService(dds_domainid_t domain) {
  auto service = std::make_unique<FakePlanningService>();
  auto participant = dds::createParticipant(domain);
  if (!participant.ok()) {
    ADD_FAILURE() << participant.error().describe();
    return nullptr;
  }
  service->participant.emplace(std::move(*participant));
  auto requests = dds::Reader<MissionRequestData>::create(service->participant->get());
  auto statuses = dds::Writer<PlanStatusData>::create(service->participant->get());
  auto heartbeat = dds::Writer<ServiceStatusData>::create(service->participant->get(),
                                                          dds::ServiceInstance::current("test-service").userData());
  if (!requests.ok() || !statuses.ok() || !heartbeat.ok()) {
    ADD_FAILURE() << "the fake planning service's readers and writers";
    return nullptr;
  }
  service->requests.emplace(std::move(*requests));
  service->statuses.emplace(std::move(*statuses));
  service->heartbeat.emplace(std::move(*heartbeat));
  if (!service->listen()) return nullptr;
  return service;
}

}  // namespace skyroute::testing
