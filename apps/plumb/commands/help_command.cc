// plumb help: the manual's pages (docs/*.md), embedded at build time, printed as they are.

#include <cstdio>
#include <set>
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

// Lists the pages: a command's first (those the app has), then the topics.
int ListPages(const CLI::App& app) {
  std::set<std::string> command_names;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    command_names.insert(command->get_name());
  }
  std::string commands, topics;
  for (std::size_t i = 0; i < kDocPageCount; ++i) {
    std::string name(kDocPages[i].name);
    (command_names.count(name) != 0 ? commands : topics) += "  " + name + "\n";
  }
  std::string out =
      "plumb help PAGE prints a page of plumb's manual (docs/PAGE.md in the source tree).\n"
      "Commands:\n" +
      commands + "Topics:\n" + topics + "Each command's options: plumb COMMAND --help.\n";
  std::fwrite(out.data(), 1, out.size(), stdout);
  return kExitOk;
}

int RunHelp(const CLI::App& app, const std::string& page) {
  if (page.empty()) return ListPages(app);
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
  help->callback([page, &app, &ctx] { ctx.action = [page, &app] { return RunHelp(app, *page); }; });
}

}  // namespace plumb::cli
