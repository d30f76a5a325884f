// The field table's `mujoco` flags (lever/fields.hpp) against MuJoCo 2.2.2's own lists of its
// arrays (mjxmacro.h): a row is marked `mujoco` exactly when mjModel/mjData has an array of that
// name with the same element type and width. (Same meaning is what tests/compile and tests/diff
// then check value by value.)
#include <catch2/catch.hpp>

#include <lever/fields.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <map>
#include <string>

#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/models.hpp>
#include <lever/harness/mujoco_arrays.hpp>

namespace {

template <class Views>
void check_flags(const Views& views, const std::map<std::string, lever::test::MjArray>& theirs) {
  for (const lever::FieldView& view : views) {
    const auto found = theirs.find(view.info->name);
    const bool same = found != theirs.end() && lever::test::same_layout(view, found->second);
    INFO(view.info->name << (found == theirs.end() ? ": MuJoCo has no array of that name"
                                                   : ": MuJoCo's has another type or width"));
    CHECK(view.info->in_mujoco == same);
  }
}

}  // namespace

TEST_CASE("the field table marks mujoco exactly the arrays MuJoCo has with that layout",
          "[fields]") {
  const std::string path = lever::test::model_path("models/arm3.xml");
  const lever::test::MjModelPtr m = lever::test::mujoco_load(path);
  const lever::test::MjDataPtr d = lever::test::mujoco_data(m.get());
  const lever::Model model = lever::mjcf::load_file(path);
  lever::Data data(model);
  data.nefc = data.nefc_max;
  check_flags(lever::model_fields(model), lever::test::mujoco_model_arrays(m.get()));
  check_flags(lever::data_fields(model, data), lever::test::mujoco_data_arrays(m.get(), d.get()));
}
