// The lean step against the whole one: step() runs forward() without the outputs nothing in a step
// reads (the geom frames of a model where nothing collides); step_all() runs
// forward() itself, as MuJoCo's mj_step does, and must write those.
// Stepped from the same state, it must leave every other array of Data, the contacts, the
// warnings and the new state bit for bit as forward() followed by the integrator does, with every
// integrator, and must not write what it skips.
#include <cstring>

#include "property_models.hpp"

namespace lever::test {

namespace {

constexpr double kMark = 12345.0;  // written into what the lean step skips: it must stay

bool skipped_by_lean_step(const Model& model, std::string_view field) {
  if (model.nsensor > 0) return false;  // sensors read the frames: the step computes them all
  return !model.contacts_possible && (field == "geom_xpos" || field == "geom_xmat");
}

void mark_skipped(const Model& model, Data& data) {
  for (FieldView& view : data_fields(model, data)) {
    if (!skipped_by_lean_step(model, view.info->name)) continue;
    for (long k = 0; k < view.size(); ++k) view.doubles()[k] = kMark;
  }
}

// step_all() writes what the lean step skips (it was marked before the step)
void check_written(const Model& model, const Data& whole) {
  for (const FieldView& view : data_fields(model, whole)) {
    if (!skipped_by_lean_step(model, view.info->name)) continue;
    INFO("Data::" << view.info->name);
    for (long k = 0; k < view.size(); ++k) CHECK(view.doubles()[k] != kMark);
  }
}

// Every array the lean step computes equals the whole step's, bit for bit (memcmp: -0 and +0 and
// NaN payloads count), and every array it skips still holds the mark.
void check_same(const Model& model, const Data& whole, const Data& lean) {
  const std::vector<FieldView> a = data_fields(model, whole), b = data_fields(model, lean);
  REQUIRE(a.size() == b.size());
  for (std::size_t f = 0; f < a.size(); ++f) {
    const std::string name = a[f].info->name;
    INFO("Data::" << name);
    REQUIRE(a[f].size() == b[f].size());
    if (skipped_by_lean_step(model, name)) {
      for (long k = 0; k < b[f].size(); ++k) CHECK(b[f].doubles()[k] == kMark);
      continue;
    }
    const std::size_t bytes = static_cast<std::size_t>(a[f].size()) *
                              (a[f].info->scalar == Scalar::kDouble ? sizeof(double)
                               : a[f].info->scalar == Scalar::kInt  ? sizeof(int)
                                                                    : 1);
    // an empty array may have no storage at all (memcmp's pointers must not be null)
    if (bytes > 0) CHECK(std::memcmp(a[f].data, b[f].data, bytes) == 0);
  }
  CHECK(whole.time == lean.time);
  CHECK(whole.ncon == lean.ncon);
  CHECK(whole.nefc == lean.nefc);
  for (int c = 0; c < whole.ncon && c < lean.ncon; ++c) {
    CHECK(whole.contact[c].dist == lean.contact[c].dist);
    CHECK(whole.contact[c].pos == lean.contact[c].pos);
    CHECK(whole.contact[c].frame == lean.contact[c].frame);
  }
  for (std::size_t w = 0; w < whole.warning.size(); ++w) {
    CHECK(whole.warning[w].number == lean.warning[w].number);
    CHECK(whole.warning[w].lastinfo == lean.warning[w].lastinfo);
  }
}

}  // namespace

TEST_CASE("property: the lean step computes what forward() and the integrator do, bit for bit",
          "[property][step]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    for (const Integrator integrator :
         {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
      Model model = c.model;
      model.opt.integrator = integrator;
      Data whole(model), lean(model);
      mark_skipped(model, lean);
      mark_skipped(model, whole);
      std::mt19937_64 rng(c.seed);
      for (int k = 0; k < kStatesPerModel / 10; ++k) {
        const auto state = random_state(model, rng);
        apply(state, whole);
        apply(state, lean);
        INFO(c.name << ", seed " << c.seed << ", " << integrator_name(integrator) << ", state "
                    << k);
        for (int s = 0; s < 2; ++s) {  // the second step starts where the first ended
          step_all(model, whole);
          step(model, lean);
          check_written(model, whole);
          check_same(model, whole, lean);
        }
      }
    }
  }
}

}  // namespace lever::test
