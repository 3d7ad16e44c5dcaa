// The repro folder of a diverged run: everything needed to reproduce it elsewhere.

#include "plumb/repro.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/strings.h"
#include "plumb/error.h"
#include "plumb/json_output.h"
#include "plumb/version.h"

namespace plumb {
using internal::ShellQuote;

namespace fs = std::filesystem;

namespace {
void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw IoError("cannot write '" + path.string() + "': " + std::strerror(errno));
}
}  // namespace

std::string WriteRepro(const Model& model, const RunResult& result,
                       const std::vector<std::string>& argv, const std::string& dir,
                       const std::string& note) {
  // pick a name that does not exist yet
  std::string final_dir = dir;
  std::error_code ec;
  for (int n = 2; fs::exists(final_dir, ec); ++n) final_dir = dir + "-" + std::to_string(n);
  fs::path temp = fs::path(final_dir).parent_path();
  if (temp.empty()) temp = ".";
  temp /= "." + fs::path(final_dir).filename().string() + ".tmp-" + std::to_string(getpid());
  fs::remove_all(temp, ec);
  if (!fs::create_directories(temp, ec)) {
    throw IoError("cannot create repro folder '" + final_dir + "': " + ec.message());
  }
  try {
    std::string command;
    for (const std::string& a : argv) command += (command.empty() ? "" : " ") + ShellQuote(a);
    // comments on their own lines, so the command line runs as written (sh command.txt)
    std::string comments = "# run from: " + fs::current_path().string() + "\n";
    if (!note.empty()) comments += "# " + note + "\n";
    WriteText(temp / "command.txt", comments + command + "\n");
    model.SaveBinary((temp / "model.mjb").string());
    std::string xml_note;
    try {
      model.SaveXml((temp / "model.xml").string());
    } catch (const IoError& e) {
      xml_note = std::string("model.xml was not written: ") + e.what() + "\n";
    }
    if (result.divergence) {
      WriteText(temp / "last_good.json", StateToJson(result.divergence->last_good));
      WriteText(temp / "bad.json", StateToJson(result.divergence->bad));
    }
    WriteText(temp / "warnings.json", WarningsToJson(result.warnings));
    WriteText(temp / "README.txt",
              "plumb " PLUMB_VERSION " repro folder, MuJoCo " + MujocoVersion() + "\n\n" +
                  (result.divergence ? result.divergence->reason + "\n\n" : "") +
                  "command.txt     the exact command line that diverged\n"
                  "model.xml       the model as MuJoCo saves it (mj_saveLastXML); runtime edits\n"
                  "                of body_mass are not written there, see model.mjb\n"
                  "model.mjb       the exact compiled model with every edit (mj_loadModel)\n"
                  "last_good.json  the state the failing step started from, with the ctrl\n"
                  "                it applied (every check passed on it)\n"
                  "bad.json        the state right after the failing step; or, when MuJoCo's\n"
                  "                own check fired and reset the data, the state it found bad\n"
                  "                with its accelerations (qacc) and a note\n"
                  "warnings.json   MuJoCo warnings raised during the run\n\n"
                  "To reproduce: load model.mjb, put last_good.json's \"integration\" into\n"
                  "an mjData (mj_setState with " +
                  std::string(IntegrationStateLayout()) +
                  "; it holds\nevery part of the state, delays' history and plastic state "
                  "included), call\nmj_forward, then mj_step once. plumb::Restore does it.\n" +
                  xml_note);
  } catch (...) {
    fs::remove_all(temp, ec);
    throw;
  }
  fs::rename(temp, final_dir, ec);
  if (ec) {
    fs::remove_all(temp, ec);
    throw IoError("cannot create repro folder '" + final_dir + "': " + ec.message());
  }
  return final_dir;
}

}  // namespace plumb
