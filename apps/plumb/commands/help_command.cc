// plumb help: the manual's pages (docs/*.md), embedded at build time, printed as they are.

#include <cstdio>
#include <string>
#include <string_view>

#include "cli_common.h"
#include "docs_pages.h"
#include "plumb/error.h"

namespace plumb::cli {
namespace {

std::string PageNames() {
  std::string names;
  for (std::size_t i = 0; i < kDocPageCount; ++i) {
    names += (i == 0 ? "" : ", ") + std::string(kDocPages[i].name);
  }
  return names;
}

int RunHelp(const std::string& page) {
  if (page.empty()) {
    std::string out =
        "plumb help PAGE prints a page of plumb's manual (docs/PAGE.md in the source tree).\n"
        "Pages:\n";
    for (std::size_t i = 0; i < kDocPageCount; ++i) {
      out += "  " + std::string(kDocPages[i].name) + "\n";
    }
    out += "Each command's options: plumb COMMAND --help.\n";
    std::fwrite(out.data(), 1, out.size(), stdout);
    return kExitOk;
  }
  for (std::size_t i = 0; i < kDocPageCount; ++i) {
    if (kDocPages[i].name == page) {
      std::string_view text = *kDocPages[i].text;
      std::fwrite(text.data(), 1, text.size(), stdout);
      return kExitOk;
    }
  }
  throw ValueError("help: no page '" + page + "'; the pages are " + PageNames() + ".");
}

}  // namespace

void SetupHelpCommand(CLI::App& app, Context& ctx) {
  auto page = std::make_shared<std::string>();
  CLI::App* help = AddCommand(app, "help", "Print a page of the manual (a command's, or a topic's)",
                              "Examples:\n  plumb help verify\n  plumb help exit-codes\n"
                              "plumb help alone lists the pages.");
  help->add_option("page", *page,
                   "a command (verify, run, ...) or a topic (paths, exit-codes, ...)");
  help->callback([page, &ctx] { ctx.action = [page] { return RunHelp(*page); }; });
}

}  // namespace plumb::cli
