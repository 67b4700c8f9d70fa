#pragma once
// The one registry of demcal's observables: the only place an observable is
// declared. Everything that names one reads it here -- the apparatus runs that
// write run records (dem/apparatus, engines/engine_measure), the readers of
// recordings, design tables and run records (config/observables,
// config/recordings_csv), the surrogates (config/surrogate_config) and the
// reports' labels (calibrate/report/labels). It lives in demcal_io, the lowest
// library, because dem/ and calibrate/ both need it and neither may depend on
// config/; it needs nothing but the standard library.
//
// To add an observable: one entry in kObservables (io/observable_registry.cpp);
// then make the apparatus that measure it write it under that name.

#include <string>
#include <string_view>
#include <vector>

namespace demcal::io {

// What a run record, a design table and a recording do with an observable.
enum class ObservableKind {
  stable,     // read from every apparatus run; a design-table column, a recording,
              // a surrogate (angle_of_repose_deg, discharge_time_s, ...)
  series,     // read off a run's m(t) series (discharge_t25_s, ...); a design-table
              // column, a recording, a surrogate, like the stable ones
  auxiliary,  // written in a run record beside the stable ones (an uncertainty, a pile's
              // height); never a design-table column, a recording or a surrogate
  trace,      // a time series a recording or a run holds (time_s,<name>); labelled in
              // the reports' figures, never a single number
};

// "stable", "series", "auxiliary", "trace"
std::string_view to_string(ObservableKind kind);

// The apparatus kinds of a study ([apparatus.<name>] type = ...), in this order.
const std::vector<std::string>& apparatus_kinds();

struct ObservableInfo {
  std::string_view name;          // "angle_of_repose_deg": the identifier, SI unit in it
  std::string_view unit;          // as a recording writes it: "deg", "s", "kg/s", "kg/m3"
  std::string_view label;         // in the reports: "angle of repose"
  std::string_view short_label;   // in tight places: "AoR"
  std::string_view display_unit;  // in the reports: "°", "s", "kg/m³"
  // The physical range a value is held to (a recording, a design-table cell, a
  // stored run outside it is refused): [lo, hi], or (lo, hi] when lo_open.
  double lo = 0.0, hi = 0.0;
  bool lo_open = false;
  std::string_view range_text;  // "a number in [0, 90] (degrees)"
  ObservableKind kind = ObservableKind::stable;
  // The apparatus kinds that measure it (apparatus_kinds() spelling): what a
  // recording of a setup of that kind may name.
  std::vector<std::string_view> measured_by;
};

// Every observable, in declaration order: the stable ones, the series ones, then
// the auxiliary ones and the traces.
const std::vector<ObservableInfo>& observable_registry();

// The entry of `name`, or nullptr when demcal knows no such observable.
const ObservableInfo* find_observable(std::string_view name);

// The names of one kind, in declaration order.
std::vector<std::string> observable_names_of_kind(ObservableKind kind);

// Whether an apparatus of `apparatus_kind` measures `observable` (false for an
// unknown observable or kind).
bool measures(std::string_view apparatus_kind, std::string_view observable);

// The stable and series observables an apparatus of `apparatus_kind` measures:
// what a recording of one of its setups may name, in declaration order.
std::vector<std::string> recordable_observables(std::string_view apparatus_kind);

// How a number is followed by its unit in a report: "°" directly ("30.96°"),
// any other unit after a space ("0.554 s").
std::string value_suffix(const ObservableInfo& observable);

// The registry as a text table, one observable a line (name, kind, unit, label,
// short label, range, measured by): for `demcal schema observables` and the docs.
std::string observable_registry_table();

}  // namespace demcal::io
