// Text helpers plumb uses everywhere and its users may too: joining and splitting, strict
// number parsing, printing that round-trips, and "did you mean" suggestions.
//
// Thread-safety: every function is pure: call them from any thread. Nothing here throws, except
// std::bad_alloc.

#ifndef PLUMB_SRC_CORE_STRINGS_H_
#define PLUMB_SRC_CORE_STRINGS_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plumb::internal {

// Joins `parts` with `separator` between them.
std::string Join(const std::vector<std::string>& parts, std::string_view separator);

// The plural of an English noun as plumb's messages name elements: "body" -> "bodies",
// "actuator" -> "actuators", "contact exclude" -> "contact excludes", "class" -> "classes".
std::string Plural(std::string_view noun);

// Parses the whole of `text` (surrounding blanks allowed) as a finite or non-finite
// double; nullopt when anything else is left over or nothing is a number.
std::optional<double> ParseNumber(std::string_view text);

// Parses a non-negative integer index ("3"); nullopt for anything else.
std::optional<long> ParseIndex(std::string_view text);

// `s` without leading and trailing white space (space, tab, newline, ...).
std::string_view Trim(std::string_view s);

// The shortest text that reads back as `value` to 6 significant digits ("%g").
std::string FormatNumber(double value);

// Splits on `separator`, keeping empty parts.
std::vector<std::string> Split(std::string_view text, char separator);

// Case-insensitive ASCII equality.
bool EqualsIgnoreCase(std::string_view a, std::string_view b);
// `s` in lower case (ASCII letters).
std::string Lowercase(std::string_view s);

// Up to `count` entries of `candidates` closest to `word` (edit distance, then
// prefix/substring matches first), for "did you mean" messages.
std::vector<std::string> Nearest(std::string_view word, const std::vector<std::string>& candidates,
                                 std::size_t count = 5);

// "did you mean: a, b, c?" or "" when there is nothing to suggest.
std::string DidYouMean(std::string_view word, const std::vector<std::string>& candidates);

// The entries of `candidates` that `word` is plausibly a typo of, nearest first (at most
// three): within an edit distance of a third of the word's length (at least 1), or
// containing it or contained in it (three characters or more). Empty when nothing is that
// close, so that a command-line typo is answered with one name, not a list of guesses.
std::vector<std::string> Closest(std::string_view word, const std::vector<std::string>& candidates);

// Quotes `arg` for a POSIX shell when it needs it: a b -> 'a b', it's -> 'it'\''s'.
std::string ShellQuote(const std::string& arg);

// `text` from a user's file as a message quotes it: at most `limit` characters (then "…" and
// the whole length: "aaaa… (102400 bytes)"), with every byte that would not print (control
// characters, a NUL, bytes that are not UTF-8) written \xNN. Every message that echoes text
// read from a file goes through it, so that binary garbage or a 100 KB line stays readable.
std::string Echo(std::string_view text, std::size_t limit = 60);

}  // namespace plumb::internal

#endif  // PLUMB_SRC_CORE_STRINGS_H_
