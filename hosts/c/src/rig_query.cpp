// What a loaded rig holds: counts, shape and part names, the neutral mesh.
#include <algorithm>

#include "boundary.h"
#include "handles.h"

using namespace facerig::capi;

namespace {

fr_status CheckIndex(std::size_t index, std::size_t count, std::string_view what) {
  if (index < count) return FR_OK;
  char i[24], n[24];
  return Fail(FR_ERROR_INVALID_ARGUMENT, {what, " index ", Number(index, i), " is out of range (the rig has ",
                                          Number(count, n), ")"});
}

}  // namespace

extern "C" {

fr_status fr_rig_get_info(const fr_rig* rig, fr_rig_info* out_info) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    FR_REQUIRE(out_info, "out_info");
    const facerig::Rig& r = rig->data->rig;
    fr_rig_info info{};
    info.vertex_count = static_cast<uint32_t>(r.vertex_count());
    info.triangle_count = static_cast<uint32_t>(r.triangle_count());
    info.shape_count = static_cast<uint32_t>(r.shape_count());
    info.part_count = static_cast<uint32_t>(r.parts().size());
    info.has_uvs = r.uvs().empty() ? 0 : 1;
    info.has_normal_deltas = r.has_normal_deltas() ? 1 : 0;
    info.units = static_cast<uint32_t>(r.units());
    info.up_axis = static_cast<uint32_t>(r.up_axis());
    info.bounding_diagonal = r.bounding_diagonal();
    *out_info = info;
    return FR_OK;
  });
}

fr_status fr_rig_shape_name(const fr_rig* rig, uint32_t index, char* buffer, size_t capacity, size_t* needed) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    const facerig::Rig& r = rig->data->rig;
    if (const fr_status s = CheckIndex(index, r.shape_count(), "shape"); s != FR_OK) return s;
    return CopyString(r.shape_name(index), buffer, capacity, needed);
  });
}

fr_status fr_rig_find_shape(const fr_rig* rig, const char* name, uint32_t* out_index) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    FR_REQUIRE(name, "name");
    FR_REQUIRE(out_index, "out_index");
    const std::optional<std::size_t> found = rig->data->rig.FindShape(name);
    if (!found) return Fail(FR_ERROR_NOT_FOUND, {"the rig has no shape named \"", name, "\""});
    *out_index = static_cast<uint32_t>(*found);
    return FR_OK;
  });
}

fr_status fr_rig_part_info(const fr_rig* rig, uint32_t index, fr_part_info* out_info) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    FR_REQUIRE(out_info, "out_info");
    const auto parts = rig->data->rig.parts();
    if (const fr_status s = CheckIndex(index, parts.size(), "part"); s != FR_OK) return s;
    const facerig::Part& part = parts[index];
    *out_info = {part.first_triangle, part.triangle_count, part.first_vertex, part.vertex_count, part.material};
    return FR_OK;
  });
}

fr_status fr_rig_part_name(const fr_rig* rig, uint32_t index, char* buffer, size_t capacity, size_t* needed) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    const auto parts = rig->data->rig.parts();
    if (const fr_status s = CheckIndex(index, parts.size(), "part"); s != FR_OK) return s;
    return CopyString(parts[index].name, buffer, capacity, needed);
  });
}

fr_status fr_rig_neutral(const fr_rig* rig, float* positions, float* normals, size_t capacity, size_t* needed) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    const facerig::Rig& r = rig->data->rig;
    if (const fr_status s = CheckCapacity(r.vertex_count(), capacity, needed, "vertices"); s != FR_OK) return s;
    if (positions) std::copy_n(&r.positions().data()->x, 3 * r.vertex_count(), positions);
    if (normals) std::copy_n(&r.normals().data()->x, 3 * r.vertex_count(), normals);
    return FR_OK;
  });
}

fr_status fr_rig_uvs(const fr_rig* rig, float* uvs, size_t capacity, size_t* needed) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    const facerig::Rig& r = rig->data->rig;
    if (r.uvs().empty()) {
      if (needed) *needed = 0;
      return Fail(FR_ERROR_NOT_FOUND, "the rig has no texture coordinates");
    }
    if (const fr_status s = CheckCapacity(r.vertex_count(), capacity, needed, "UVs"); s != FR_OK) return s;
    FR_REQUIRE(uvs, "uvs");
    std::copy_n(&r.uvs().data()->x, 2 * r.vertex_count(), uvs);
    return FR_OK;
  });
}

fr_status fr_rig_triangles(const fr_rig* rig, uint32_t* indices, size_t capacity, size_t* needed) {
  return Guard([&] {
    FR_REQUIRE(rig, "rig");
    const facerig::Rig& r = rig->data->rig;
    if (const fr_status s = CheckCapacity(r.triangle_count(), capacity, needed, "triangles"); s != FR_OK) return s;
    FR_REQUIRE(indices, "indices");
    std::copy_n(r.triangles().data()->data(), 3 * r.triangle_count(), indices);
    return FR_OK;
  });
}

}  // extern "C"
