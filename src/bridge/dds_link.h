// CycloneDDS (its C API) for the bridge: a domain on loopback, and typed writers and
// readers of the messages idlc generates from idl/.
//
// Loopback by default: the domain binds to `lo`, sends no multicast, and finds its peers at
// 127.0.0.1 (participant indices up to 50), so a controller on the same machine needs no
// set-up and nothing leaves it. Readers are best-effort with a history of one (they match
// best-effort and reliable writers alike, as Unitree's SDK's are); writers are reliable.

#ifndef PLUMB_SRC_BRIDGE_DDS_LINK_H_
#define PLUMB_SRC_BRIDGE_DDS_LINK_H_

#include <dds/dds.h>

#include <cstdint>
#include <string>

namespace plumb::bridge {

// The CycloneDDS configuration (XML) of a loopback-only domain.
std::string LoopbackConfig();

// Throws UnavailableError "DDS: <what> failed: <CycloneDDS's reason>" when `rc` < 0.
void CheckDds(dds_return_t rc, const std::string& what);

// A domain and its participant, deleted (with every entity made from it) on destruction. A
// second DdsDomain of the same id in one process joins the first one's domain (CycloneDDS
// keeps one domain entity per id per process), so a controller and the bridge can share a
// program, as they do in tests.
class DdsDomain {
 public:
  // @throws UnavailableError saying why when CycloneDDS cannot start (e.g. `lo` is missing);
  //         ValueError for an id above 232.
  DdsDomain(std::uint32_t domain_id, const std::string& config = LoopbackConfig());
  DdsDomain(const DdsDomain&) = delete;
  DdsDomain& operator=(const DdsDomain&) = delete;
  ~DdsDomain();
  dds_entity_t participant() const { return participant_; }
  std::uint32_t id() const { return id_; }

 private:
  std::uint32_t id_;
  dds_entity_t domain_ = 0;
  dds_entity_t participant_ = 0;
};

// Writes samples of one generated type on one topic.
template <typename T>
class DdsWriter {
 public:
  DdsWriter(const DdsDomain& domain, const std::string& topic, const dds_topic_descriptor_t* type) {
    dds_entity_t t = dds_create_topic(domain.participant(), type, topic.c_str(), nullptr, nullptr);
    CheckDds(t, "creating topic " + topic);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
    writer_ = dds_create_writer(domain.participant(), t, qos, nullptr);
    dds_delete_qos(qos);
    CheckDds(writer_, "creating a writer of " + topic);
  }
  void Write(const T& sample) { CheckDds(dds_write(writer_, &sample), "writing"); }
  // How many readers are matched now.
  int Matched() const {
    dds_publication_matched_status_t s;
    return dds_get_publication_matched_status(writer_, &s) == DDS_RETCODE_OK
               ? static_cast<int>(s.current_count)
               : 0;
  }

 private:
  dds_entity_t writer_ = 0;
};

// Takes samples of one generated type from one topic.
template <typename T>
class DdsReader {
 public:
  DdsReader(const DdsDomain& domain, const std::string& topic, const dds_topic_descriptor_t* type) {
    dds_entity_t t = dds_create_topic(domain.participant(), type, topic.c_str(), nullptr, nullptr);
    CheckDds(t, "creating topic " + topic);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
    reader_ = dds_create_reader(domain.participant(), t, qos, nullptr);
    dds_delete_qos(qos);
    CheckDds(reader_, "creating a reader of " + topic);
  }
  // Takes one waiting sample into `out`; false when none is waiting. `writer`, when given,
  // receives the handle of the DataWriter that published it (one per controller).
  bool Take(T* out, dds_instance_handle_t* writer = nullptr) {
    void* samples[1] = {out};
    dds_sample_info_t info;
    for (;;) {
      dds_return_t n = dds_take(reader_, samples, &info, 1, 1);
      CheckDds(n, "taking a sample");
      if (n == 0) return false;
      if (!info.valid_data) continue;  // a disposal notice: look further
      if (writer != nullptr) *writer = info.publication_handle;
      return true;
    }
  }
  // Waits up to `timeout` for data; true when some is waiting.
  bool Wait(dds_duration_t timeout) {
    dds_entity_t waitset = dds_create_waitset(dds_get_participant(reader_));
    dds_entity_t condition = dds_create_readcondition(reader_, DDS_ANY_STATE);
    dds_waitset_attach(waitset, condition, 0);
    dds_return_t n = dds_waitset_wait(waitset, nullptr, 0, timeout);
    dds_delete(condition);
    dds_delete(waitset);
    return n > 0;
  }

 private:
  dds_entity_t reader_ = 0;
};

}  // namespace plumb::bridge

#endif  // PLUMB_SRC_BRIDGE_DDS_LINK_H_
