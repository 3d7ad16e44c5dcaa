// What a call says besides its result: warnings, notes and hints, on one channel.
//
// A library call that has something to tell its user (MuJoCo's compiler warnings, a ctrl
// outside its ctrlrange, a log whose last line was cut, how many rollouts a stop kept) adds a
// Notice to the Notices it is given. The front ends decide how to present them, never what to
// say: the plumb command prints each as a line on stderr ("plumb: warning: SUBJECT: TEXT"),
// Python issues each through `warnings` with plumb's warning class for its topic (so users
// can filter them) and keeps them on the result (`.notes`), and JSON carries them (NoticesToJson).
//
//   plumb::Notices notices([](const plumb::Notice& n) { std::fprintf(stderr, "%s\n", ...); });
//   plumb::Model model = plumb::LoadModel(path, &notices);   // compile warnings, as they come
//
// Thread-safety: Add may be called from any thread; the listener is called under the
// collection's lock, one notice at a time, on the thread that added it.

#ifndef PLUMB_INCLUDE_PLUMB_NOTICE_H_
#define PLUMB_INCLUDE_PLUMB_NOTICE_H_

#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace plumb {

// How much a notice matters: a warning says a result may not mean what the user thinks; a
// note says what plumb did on the user's behalf (skipped, resumed, clamped on purpose); a
// hint says what the user could do next.
enum class NoticeLevel { kWarning, kNote, kHint };

// What a notice is about. Each topic is one Python warning class (plumb.CompileWarning, ...);
// add a topic only with its class (python/src/common.cc) and its name below.
enum class NoticeTopic {
  kCompile,    // MuJoCo's compiler or loader on the model (CompileWarning)
  kStart,      // a start value the model changes: a ctrl outside its range (StartWarning)
  kLog,        // a robot log: a cut last line, a column left out (LogWarning)
  kBatch,      // a rollout, sweep or identify run: resumed, stopped, cases skipped (BatchWarning)
  kModel,      // the model as a check reads it: a field that changes nothing (ModelWarning)
  kOther,      // anything else (PlumbWarning)
};

// "compile", "start", "log", "batch", "model", "other": JSON's and Python's name of a topic.
const char* TopicName(NoticeTopic topic);
// "warning", "note", "hint".
const char* LevelName(NoticeLevel level);

struct Notice {
  NoticeLevel level = NoticeLevel::kWarning;
  NoticeTopic topic = NoticeTopic::kOther;
  // What it is about, as the user named it: a file ("models/g1.xml"), an option as written
  // ("--set 'ctrl[hip]=5'"), or empty.
  std::string subject;
  std::string text;  // one or more sentences, no trailing newline

  // "warning: SUBJECT: TEXT" (the level, then the subject when there is one): the line the
  // plumb command prints after "plumb: ", and Python's warning message.
  std::string Line() const;
};

// A collection of notices that hands each to a listener as it is added.
class Notices {
 public:
  using Listener = std::function<void(const Notice&)>;

  explicit Notices(Listener listener = {}) : listener_(std::move(listener)) {}
  Notices(const Notices&) = delete;
  Notices& operator=(const Notices&) = delete;

  void Add(Notice notice);
  void Warn(NoticeTopic topic, std::string subject, std::string text) {
    Add({NoticeLevel::kWarning, topic, std::move(subject), std::move(text)});
  }
  void Note(NoticeTopic topic, std::string subject, std::string text) {
    Add({NoticeLevel::kNote, topic, std::move(subject), std::move(text)});
  }
  void Hint(NoticeTopic topic, std::string subject, std::string text) {
    Add({NoticeLevel::kHint, topic, std::move(subject), std::move(text)});
  }

  // Every notice added so far, in order (a copy: other threads may still add).
  std::vector<Notice> all() const;

 private:
  Listener listener_;
  mutable std::mutex mutex_;
  std::vector<Notice> notices_;
};

// Adds `notice` to `sink` when `sink` is not null (a call's optional channel).
inline void AddTo(Notices* sink, Notice notice) {
  if (sink != nullptr) sink->Add(std::move(notice));
}

// [{"level": "warning", "topic": "compile", "subject": "...", "text": "..."}, ...]
std::string NoticesToJson(const std::vector<Notice>& notices);

// `json`, a command's JSON document (an object), with "notices": NoticesToJson(notices) added
// as its last member, laid out as the document was (indented by two, or on one line). How the
// plumb command's --format json and Python's to_json() carry a call's notices.
// @throws InternalError (PLUMB_DEMAND) when `json` is not a JSON object.
std::string JsonWithNotices(const std::string& json, const std::vector<Notice>& notices);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_NOTICE_H_
