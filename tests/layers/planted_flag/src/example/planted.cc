// A library string that names a command-line flag: tests/no_flags_in_library.sh must refuse it
// (the test LibraryNamesNoFlagsRefusesAPlantedFlag). Never compiled.
const char* kAdvice = "run longer: --until 10";
