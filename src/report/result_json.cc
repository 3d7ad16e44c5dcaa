// The JSON documents of plumb's results (include/plumb/result_json.h).

#include "plumb/result_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "plumb/model.h"

namespace plumb {
namespace {

using Json = nlohmann::ordered_json;

Json Number(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

// The number, else the text, else null.
Json NumberOrText(const Quantity& q, const std::string& text) {
  if (q.known()) return q.value;
  if (text.empty()) return nullptr;
  return text;
}

Json RowJson(const CheckRow& row) {
  return {{"id", row.id},
          {"section", row.section},
          {"title", row.title},
          {"status", CheckStatusName(row.status)},
          {"element", row.About()},
          {"element_type", row.element.kind},
          {"element_name", row.element.name},
          {"element_id", row.element.id},
          {"measured", NumberOrText(row.measured, row.measured_text)},
          {"measured_unit", row.measured.unit},
          {"measured_text", row.measured_text},
          {"reference", NumberOrText(row.reference, row.reference_text)},
          {"reference_unit", row.reference.unit},
          {"reference_text", row.reference_text},
          {"threshold", row.threshold},
          {"rel_error", Number(row.rel_error)},
          {"explanation", row.explanation},
          {"fix", row.fix}};
}

Json Summary(const std::vector<CheckRow>& rows) {
  return {{"pass", CountStatus(rows, CheckStatus::kPass)},
          {"warn", CountStatus(rows, CheckStatus::kWarn)},
          {"fail", CountStatus(rows, CheckStatus::kFail)},
          {"skip", CountStatus(rows, CheckStatus::kSkip)}};
}

}  // namespace

std::string VerifyToJson(const VerifyReport& report) {
  Json j;
  j["model"] = report.model;
  j["mujoco_version"] = MujocoVersion();
  j["tol"] = report.tol;
  Json checks = Json::array();
  for (const CheckRow& row : report.checks) checks.push_back(RowJson(row));
  j["checks"] = checks;
  j["summary"] = Summary(report.checks);
  return j.dump(2) + "\n";
}

std::string AuditToJson(const AuditReport& report) {
  Json j;
  j["model"] = report.model;
  j["mujoco_version"] = MujocoVersion();
  Json layers = Json::object();
  for (const CheckRow& row : report.findings) layers[row.section].push_back(RowJson(row));
  j["layers"] = layers;
  j["repro_folders"] = report.repro_folders;
  j["summary"] = Summary(report.findings);
  return j.dump(2) + "\n";
}

}  // namespace plumb
