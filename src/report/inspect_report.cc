// plumb.inspect's page (include/plumb/report.h): the description as tables with units.

#include <fmt/format.h>

#include "plumb/report.h"
#include "report/page_start.h"

namespace plumb {
namespace {

using report::Escape;

std::string Num(double v) { return fmt::format("{:.6g}", v); }
std::string Vec(const std::array<double, 3>& v) {
  return fmt::format("{:.6g} {:.6g} {:.6g}", v[0], v[1], v[2]);
}
std::string Range(bool limited, const std::array<double, 2>& r, const std::string& unit) {
  return limited ? fmt::format("[{:.6g}, {:.6g}] {}", r[0], r[1], unit)
                 : "unlimited (" + unit + ")";
}

// An HTML table of text cells (each escaped), or a paragraph saying there is nothing.
std::string Table(const std::vector<std::string>& head,
                  const std::vector<std::vector<std::string>>& rows, const std::string& none) {
  if (rows.empty()) return "<p>" + Escape(none) + "</p>\n";
  std::string html = "<table><tr>";
  for (const std::string& h : head) html += "<th>" + Escape(h) + "</th>";
  html += "</tr>";
  for (const auto& row : rows) {
    html += "<tr>";
    for (const std::string& cell : row) html += "<td>" + Escape(cell) + "</td>";
    html += "</tr>";
  }
  return html + "</table>\n";
}

}  // namespace

void WriteInspectReport(const std::string& path, const Model& model, const ModelDescription& d,
                        const ReportInfo& info) {
  report::Page page = report::StartPage("inspect", model, info);
  page.Meta("model name", d.model_name);
  page.Heading("Sizes and options");
  std::vector<std::vector<std::string>> rows;
  for (const auto& [name, value] : d.sizes) rows.push_back({name, std::to_string(value)});
  rows.push_back({"opt.timestep", Num(d.timestep) + " s"});
  rows.push_back({"opt.integrator", d.integrator});
  rows.push_back({"opt.gravity", Vec(d.gravity) + " m/s^2"});
  page.Html(Table({"size or option", "value"}, rows, ""));
  page.Heading(fmt::format("Bodies (total mass {:.6g} kg)", d.total_mass));
  rows.clear();
  for (const BodyDescription& b : d.bodies) {
    rows.push_back({std::to_string(b.id), b.name, std::to_string(b.parent), Num(b.mass), Vec(b.com),
                    Vec(b.inertia)});
  }
  page.Html(Table(
      {"id", "name", "parent", "mass [kg]", "com in body frame [m]", "principal inertia [kg*m^2]"},
      rows, "(none)"));
  page.Heading("Joints");
  rows.clear();
  for (const JointDescription& j : d.joints) {
    rows.push_back({std::to_string(j.id), j.name, j.type, std::to_string(j.body),
                    std::to_string(j.qposadr), std::to_string(j.dofadr),
                    j.limited ? Range(true, j.range, j.position_unit) : "unlimited", Num(j.damping),
                    Num(j.armature)});
  }
  page.Html(
      Table({"id", "name", "type", "body", "qposadr", "dofadr", "range", "damping", "armature"},
            rows, "(none)"));
  page.Paragraph("Damping in N*m*s/rad (hinge) or N*s/m (slide); armature in kg*m^2 or kg.");
  page.Heading("Actuators");
  rows.clear();
  for (const ActuatorDescription& a : d.actuators) {
    rows.push_back({std::to_string(a.id), a.name, a.kind, a.transmission + ":" + a.target,
                    Num(a.gear), Range(a.ctrllimited, a.ctrlrange, a.ctrl_unit),
                    Range(a.joint_force_limited, a.joint_force_range, a.joint_force_unit),
                    a.forcelimited ? Range(true, a.forcerange, a.force_unit) : "unlimited"});
  }
  page.Html(
      Table({"id", "name", "kind", "drives", "gear", "ctrlrange", "joint force", "forcerange"},
            rows, "(none: a passive system, ctrl is empty)"));
  page.Heading("Sensors");
  rows.clear();
  for (const SensorDescription& s : d.sensors) {
    rows.push_back({std::to_string(s.id), s.name, s.type,
                    fmt::format("sensordata[{}..{}]", s.adr, s.adr + s.dim - 1),
                    s.unit.empty() ? "-" : s.unit});
  }
  page.Html(Table({"id", "name", "type", "entries", "unit"}, rows, "(none: sensordata is empty)"));
  if (!d.delays.empty()) {
    page.Heading("Delays");
    rows.clear();
    for (const DelayDescription& delay : d.delays) {
      rows.push_back({delay.kind, std::to_string(delay.id), delay.name, Num(delay.delay),
                      std::to_string(delay.nsample), Num(delay.buffer), delay.Warning()});
    }
    page.Html(
        Table({"kind", "id", "name", "delay [s]", "nsample", "buffer [s]", "warning"}, rows, ""));
  }
  page.Heading("What is what");
  rows.clear();
  for (const RoleDescription& r : d.roles)
    rows.push_back({r.role, r.where, r.examples, r.who_writes});
  page.Html(Table({"role", "where", "fields", "written by"}, rows, ""));
  page.Paragraph("Units: length m, mass kg, time s, angle rad, torque N*m, force N.");
  report::WritePage(page, path);
}

}  // namespace plumb
