// What every report begins with and ends with: the header (model, hash, versions, command
// line, date, renderer), pictures of the model, and the atomic write.

#ifndef PLUMB_SRC_REPORT_PAGE_START_H_
#define PLUMB_SRC_REPORT_PAGE_START_H_

#include <string>
#include <vector>

#include "plumb/model.h"
#include "plumb/path.h"
#include "plumb/report.h"
#include "report/html.h"

namespace plumb::report {

// A page titled "plumb <command> <model file>" with the header filled in.
Page StartPage(const std::string& command, const Model& model, const ReportInfo& info);

// Pictures of the model at t = 0 and at the end of the nominal run (info.nominal_until s,
// started from `sets`), and a short animation of that run; a note instead when the
// renderer cannot run. Adds a "renderer" line to the header. Takes them from info.ahead when
// StartPictures began them, else draws them now.
void AddModelPictures(Page* page, const Model& model, const std::vector<Assignment>& sets,
                      const ReportInfo& info);

// Thumbnails (PNG bytes) of the model at the start state of `pictures` with each of
// `elements` (names of bodies, geoms or joints) highlighted, in order, drawn by the pictures'
// own renderer at half their size; empty when the renderer cannot run (and `why` says why).
// Asked once of a PicturesAhead.
std::vector<std::string> HighlightThumbnails(PicturesAhead& pictures,
                                             const std::vector<std::string>& elements,
                                             std::string* why);

// Writes the page through AtomicFile. @throws IoError naming `path`.
void WritePage(const Page& page, const std::string& path);

}  // namespace plumb::report

#endif  // PLUMB_SRC_REPORT_PAGE_START_H_
