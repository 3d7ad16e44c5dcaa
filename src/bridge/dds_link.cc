// The loopback domain (dds_link.h).

#include "bridge/dds_link.h"

#include "plumb/bridge.h"
#include "plumb/error.h"

namespace plumb::bridge {

std::string LoopbackConfig() { return BridgeLoopbackConfig(); }

void CheckDds(dds_return_t rc, const std::string& what) {
  if (rc < 0) {
    throw UnavailableError("DDS: " + what + " failed: " + dds_strretcode(rc));
  }
}

DdsDomain::DdsDomain(std::uint32_t domain_id, const std::string& config) : id_(domain_id) {
  if (domain_id > 232) {
    throw ValueError("DDS domain id " + std::to_string(domain_id) +
                     ": RTPS allows 0 to 232 (each id maps to its own UDP ports)");
  }
  domain_ = dds_create_domain(domain_id, config.c_str());
  // already made in this process (a controller in the same program): join it
  if (domain_ == DDS_RETCODE_PRECONDITION_NOT_MET) domain_ = 0;
  CheckDds(domain_, "starting domain " + std::to_string(domain_id) + " on loopback");
  participant_ = dds_create_participant(domain_id, nullptr, nullptr);
  if (participant_ < 0) {
    if (domain_ > 0) dds_delete(domain_);
    CheckDds(participant_, "creating a participant in domain " + std::to_string(domain_id));
  }
}

DdsDomain::~DdsDomain() {
  if (participant_ > 0) dds_delete(participant_);
  if (domain_ > 0) dds_delete(domain_);
}

}  // namespace plumb::bridge
