#include "verify_bindings.h"

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "base/errors.h"
#include "base/text_file.h"
#include "harness/commands/command_options.h"
#include "harness/commands/external_verify.h"
#include "harness/commands/image_set_verify.h"
#include "harness/plan/estimates_file.h"
#include "harness/session/publish.h"
#include "harness/session/report.h"
#include "image_arrays.h"

namespace pcbench::python {
namespace {

namespace py = pybind11;

// What a verification hands back to Python: the report's JSON text, the folder it was written
// to (none when in memory), whether everything came out as expected, what it said on stderr.
struct Published {
  std::string report;
  std::optional<std::string> folder;
  bool as_expected = false;
  std::string warnings;
};

py::dict to_python(const Published& p) {
  py::dict d;
  d["report"] = p.report;
  d["out"] = p.folder ? py::object(py::str(*p.folder)) : py::object(py::none());
  d["as_expected"] = p.as_expected;
  d["warnings"] = p.warnings;
  return d;
}

// The session options of a verification called from Python: the CLI's defaults with `alpha`
// and `out`, and the call named where the report says which command made it.
SessionOptions call_options(double alpha, const std::optional<std::string>& out,
                            const std::string& call) {
  if (!(alpha > 0.0 && alpha < 1.0)) {
    throw InputError(fmt::format("alpha {}: alpha must be in (0, 1)", alpha));
  }
  if (out) check_out_dir(*out, true);
  SessionOptions options;
  options.alpha = alpha;
  options.out_dir = out;
  options.quiet = true;
  options.threads = thread_count(0);
  options.argv = {call};
  return options;
}

// The report: published into options.out_dir (the CLI's way) and read back, or built in memory.
// Runs without the GIL.
template <class Publish>
Published publish(const SessionOptions& options, const ReportSections& sections, bool echo,
                  bool as_expected, const Publish& write_it) {
  Published p{.report = {}, .folder = options.out_dir, .as_expected = as_expected, .warnings = {}};
  if (!options.out_dir) {
    p.report = report_json(session_context(options), options.suite_name, {}, sections);
    return p;
  }
  std::ostringstream quiet, err;
  if (!write_it(echo ? static_cast<std::ostream&>(std::cout) : quiet, err)) {
    throw std::runtime_error(err.str());
  }
  p.warnings = err.str();
  p.report = read_text_file(report_folder(options) / "report.json", "the report");
  return p;
}

// Three channel names (files) or indices (arrays), or none.
void read_channels(const py::object& channels, ImageSetRequest& request,
                   std::optional<ChannelIndices>& indices) {
  if (channels.is_none()) return;
  const auto items = channels.cast<std::vector<py::object>>();
  if (items.size() != kImageChannels) {
    throw InputError(
        fmt::format("channels: {} given; give three (names for files, indices for "
                    "arrays), filling R, G, B",
                    items.size()));
  }
  if (py::isinstance<py::str>(items[0])) {
    request.read.channels.clear();
    for (const py::object& item : items) request.read.channels.push_back(item.cast<std::string>());
    return;
  }
  indices.emplace();
  for (std::size_t c = 0; c < kImageChannels; ++c) (*indices)[c] = items[c].cast<std::size_t>();
}

// A side of the comparison: a SET of files as the CLI takes it (str), or an array.
bool is_files(const py::object& side) {
  return py::isinstance<py::str>(side);
}

py::dict images_call(const py::object& a, const py::object& against, const py::object& reference,
                     const py::object& reference_stderr, const std::optional<std::string>& constant,
                     double alpha, std::uint32_t tile, const py::object& channels, bool paired,
                     const std::string& expect, const std::optional<std::string>& out, bool echo) {
  ImageSetRequest request;
  std::optional<ChannelIndices> indices;
  read_channels(channels, request, indices);
  const auto label = [](const py::object& side, const char* name) {
    return is_files(side) ? side.cast<std::string>()
                          : fmt::format("{}: {}", name, describe_array(py::array(side)));
  };
  request.images = label(a, "a");
  if (!against.is_none()) request.against = label(against, "against");
  if (!reference.is_none()) request.reference_image = label(reference, "reference");
  if (!reference_stderr.is_none()) {
    request.reference_stderr = label(reference_stderr, "reference_stderr");
  }
  request.constant = constant;
  request.tile = tile;
  request.expect = expect;
  request.paired = paired;
  const SessionOptions options = call_options(alpha, out, "pcbench.verify_images");
  check_image_set_request(request, options);

  ImagesInMemory loaded;
  if (!is_files(a)) loaded.set = image_set_from_array(py::array(a), "a", indices);
  if (!against.is_none() && !is_files(against)) {
    loaded.other = image_set_from_array(py::array(against), "against", indices);
  }
  if (!reference.is_none() && !is_files(reference)) {
    if (!reference_stderr.is_none() && is_files(reference_stderr)) {
      throw InputError("reference_stderr: a file goes with a reference file; give an array");
    }
    loaded.reference = image_from_array(py::array(reference), "reference", indices);
    loaded.reference_pixel_type = pixel_type_of(py::array(reference));
    if (!reference_stderr.is_none()) {
      loaded.reference_stderr =
          image_from_array(py::array(reference_stderr), "reference_stderr", indices);
    }
  }
  Published published;
  {
    const py::gil_scoped_release release;
    const ImageSetInput input = read_image_set_input(request, std::move(loaded));
    ImageSetVerification verification = verify_image_set(request, input, options);
    const bool as_expected = comparisons_as_expected(verification.comparisons);
    const ReportSections sections = image_set_sections(verification);
    published =
        publish(options, sections, echo, as_expected, [&](std::ostream& o, std::ostream& e) {
          return publish_image_set_verification(std::move(verification), options, o, e) !=
                 kExitRunFailed;
        });
  }
  return to_python(published);
}

py::dict estimates_call(const std::vector<double>& x,
                        const std::optional<std::vector<double>>& against,
                        const std::optional<std::string>& reference, double alpha,
                        const std::string& expect, const std::optional<std::string>& out,
                        bool echo) {
  ExternalRequest request{.estimates = fmt::format("x: array of {} estimates", x.size()),
                          .run_id = std::nullopt,
                          .reference = reference,
                          .against = std::nullopt,
                          .expect = expect};
  if (against) request.against = fmt::format("against: array of {} estimates", against->size());
  if (expect != "consistent" && expect != "biased") {
    throw InputError(fmt::format("expect '{}': consistent or biased", expect));
  }
  check_external_request(request);
  const SessionOptions options = call_options(alpha, out, "pcbench.verify_estimates");
  check_estimates(x, "x");
  if (against) check_estimates(*against, "against");
  const std::vector<double> none;
  const EstimatesVerification verification =
      verify_estimates(x, against ? *against : none, request, options);
  const Verdict& verdict = verification.verdict;
  ReportSections sections;
  sections.external.push_back(verification.external);
  Published published;
  {
    const py::gil_scoped_release release;
    published = publish(
        options, sections, echo, verdict.result == verdict.expect,
        [&](std::ostream& o, std::ostream& e) { return publish_report(options, sections, o, e); });
  }
  return to_python(published);
}

}  // namespace

void add_verify_bindings(py::module_& module) {
  module.def("_verify_images", &images_call, py::arg("a"), py::arg("against"), py::arg("reference"),
             py::arg("reference_stderr"), py::arg("constant"), py::arg("alpha"), py::arg("tile"),
             py::arg("channels"), py::arg("paired"), py::arg("expect"), py::arg("out"),
             py::arg("echo"), "verify --images on arrays or files (see pcbench.verify_images)");
  module.def("_verify_estimates", &estimates_call, py::arg("x"), py::arg("against"),
             py::arg("reference"), py::arg("alpha"), py::arg("expect"), py::arg("out"),
             py::arg("echo"), "verify --estimates on arrays (see pcbench.verify_estimates)");
}

}  // namespace pcbench::python
