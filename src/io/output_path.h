// Outputs that would destroy their inputs: a command's or a call's output file (or folder) that
// is one of the files it reads, under any name.

#ifndef PLUMB_SRC_IO_OUTPUT_PATH_H_
#define PLUMB_SRC_IO_OUTPUT_PATH_H_

#include <string>
#include <vector>

namespace plumb::internal {

// A file a command or call is given, and how its caller names it in a message: the option or
// argument for an output ("-o", "output"), a phrase for an input ("the model", "the log").
struct NamedPath {
  std::string name;
  std::string path;
};

// True when `a` and `b` both exist and are the same file or folder, whatever names reach it:
// relative or absolute, with "./" or "..", through symbolic links or hard links. Never throws.
bool SameFile(const std::string& a, const std::string& b);

// Refuses an output that is one of the inputs, before anything is written. An output that does
// not exist yet is no input; nor is one that is not a regular file or a folder (standard output
// "-", a FIFO, a terminal, a device: written directly, never replaced). Empty paths are skipped.
// @throws ArgumentError whose argument() is the output's name and value() its path quoted,
// naming the input it would destroy.
void RefuseOutputsOntoInputs(const std::vector<NamedPath>& outputs,
                             const std::vector<NamedPath>& inputs);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_IO_OUTPUT_PATH_H_
