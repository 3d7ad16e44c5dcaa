// plumb merge: results stores (shards of one batch, say) joined into one.

#include <memory>
#include <string>
#include <vector>

#include "cli_common.h"
#include "plumb/error.h"
#include "plumb/store.h"

namespace plumb::cli {
using internal::NamedPath;
using internal::RefuseOutputsOntoInputs;

void SetupMergeCommand(CLI::App& app, Context& ctx) {
  auto inputs = std::make_shared<std::vector<std::string>>();
  auto output = std::make_shared<std::string>();
  CLI::App* merge =
      AddCommand(app, "merge", "Join results stores (e.g. shards) into one",
                 "Example:\n  plumb merge shard0.sqlite shard1.sqlite -o all.sqlite\n"
                 "Runs with the same configuration become one; the output must not exist yet.");
  merge->add_option("inputs", *inputs, "stores to join")->required();
  merge->add_option("-o,--output", *output, "the new store")->required();
  merge->callback([inputs, output, &ctx] {
    ctx.action = [inputs, output] {
      if (*output == "-") {
        throw ValueError(
            "merge -o -: a results store is an SQLite file and cannot go to standard output; "
            "give a file name, then print it with plumb results FILE.");
      }
      std::vector<NamedPath> stores;
      for (const std::string& input : *inputs) stores.push_back({"the input store", input});
      RefuseOutputsOntoInputs({{"-o", *output}}, stores);
      MergeStores(*inputs, *output);
      return static_cast<int>(kExitOk);
    };
  });
}

}  // namespace plumb::cli
