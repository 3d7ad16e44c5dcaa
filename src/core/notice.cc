// The channel for what a call says besides its result (plumb/notice.h).

#include "plumb/notice.h"

#include <nlohmann/json.hpp>

#include "core/demand.h"

namespace plumb {

const char* TopicName(NoticeTopic topic) {
  switch (topic) {
    case NoticeTopic::kCompile: return "compile";
    case NoticeTopic::kStart: return "start";
    case NoticeTopic::kLog: return "log";
    case NoticeTopic::kBatch: return "batch";
    case NoticeTopic::kModel: return "model";
    case NoticeTopic::kOther: break;
  }
  return "other";
}

const char* LevelName(NoticeLevel level) {
  switch (level) {
    case NoticeLevel::kWarning: return "warning";
    case NoticeLevel::kNote: return "note";
    case NoticeLevel::kHint: return "hint";
  }
  return "warning";
}

std::string Notice::Line() const {
  std::string line = LevelName(level);
  line += ": ";
  if (!subject.empty()) line += subject + ": ";
  return line + text;
}

void Notices::Add(Notice notice) {
  std::lock_guard<std::mutex> lock(mutex_);
  notices_.push_back(std::move(notice));
  if (listener_) listener_(notices_.back());
}

std::vector<Notice> Notices::all() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return notices_;
}

std::string NoticesToJson(const std::vector<Notice>& notices) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const Notice& n : notices) {
    out.push_back({{"level", LevelName(n.level)},
                   {"topic", TopicName(n.topic)},
                   {"subject", n.subject},
                   {"text", n.text}});
  }
  // a path's bytes need not be UTF-8: replaced, not refused
  return out.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::string JsonWithNotices(const std::string& json, const std::vector<Notice>& notices) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(json, nullptr, false);
  PLUMB_DEMAND(doc.is_object());
  doc["notices"] = nlohmann::ordered_json::parse(NoticesToJson(notices));
  bool indented = json.find('\n') != std::string::npos;
  bool newline = !json.empty() && json.back() == '\n';
  return doc.dump(indented ? 2 : -1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) +
         (newline ? "\n" : "");
}

}  // namespace plumb
