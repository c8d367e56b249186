// Contacts across an opening (offline/src/openings_contacts.h) on a sheet
// with a slit: the slit's upper edge closing onto its lower edge is a
// contact; the same motion on a sheet without the slit is skin compressing,
// not a contact.
#include "openings/contacts.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <vector>

#include "facerig/offline/error.h"
#include "facerig/offline/geometry/mesh_components.h"
#include "support/slit_sheet.h"

namespace {

using facerig::test::SlitSheet;
using namespace facerig::test::slit;

struct Sheet {
  std::vector<glm::vec3> neutral;
  std::vector<facerig::Triangle> triangles;
  std::vector<std::uint32_t> component;
};

Sheet MakeSheet(bool slit) {
  SlitSheet grid = facerig::test::MakeSlitSheet(slit);
  Sheet sheet{std::move(grid.positions), std::move(grid.triangles), {}};
  facerig::ConnectedComponents(sheet.neutral.size(), sheet.triangles, sheet.component);
  return sheet;
}

// The slit closes (facerig::test::SlitBlinkDeltas): its upper edge stops 0.02
// above the lower one.
std::vector<glm::vec3> CloseSlit(const Sheet& sheet) {
  std::vector<glm::vec3> expression = sheet.neutral;
  const std::vector<glm::vec3> blink = facerig::test::SlitBlinkDeltas();
  for (std::size_t v = 0; v < blink.size(); ++v) expression[v] += blink[v];
  return expression;
}

// Every vertex an unknown of the solve (free_index 0..n-1), so any may be a moving end.
std::vector<std::int32_t> AllFree(std::size_t vertex_count) {
  std::vector<std::int32_t> free_index(vertex_count);
  std::iota(free_index.begin(), free_index.end(), 0);
  return free_index;
}

// One sheet's closed slit searched for contacts, with the finder and its
// scratch kept across searches.
struct ClosedSlitSearch {
  explicit ClosedSlitSearch(const Sheet& sheet)
      : expression(CloseSlit(sheet)),
        finder(sheet.neutral, sheet.triangles, sheet.component),
        all_free(AllFree(sheet.neutral.size())) {}

  const std::vector<facerig::OpeningContact>& Find(const std::vector<std::int32_t>& free_index) {
    finder.Find(expression, 0.98f, free_index, contacts, scratch);
    return contacts;
  }

  std::vector<glm::vec3> expression;
  facerig::ContactFinder finder;
  std::vector<std::int32_t> all_free;
  std::vector<facerig::OpeningContact> contacts;
  facerig::ContactFinder::Scratch scratch;
};

}  // namespace

TEST_CASE("Expression contacts: a slit closing is a contact", "[expression_contacts]") {
  const Sheet sheet = MakeSheet(true);
  ClosedSlitSearch search(sheet);
  const std::vector<facerig::OpeningContact>& contacts = search.Find(search.all_free);
  // Each vertex of the upper edge meets the one below it, 0.02 above it.
  REQUIRE(contacts.size() == kSlitLast - kSlitFirst - 1);
  for (const facerig::OpeningContact& contact : contacts) {
    const std::uint32_t x = contact.moving % kColumns;
    CHECK(contact.moving == Vertex(x, kSlitRow + 1));
    CHECK(contact.partner == Vertex(x, kSlitRow));
    CHECK(glm::length(contact.offset - glm::vec3(0.0f, 0.02f, 0.0f)) < 1e-5f);
  }
  // Pinned vertices (free_index -1) are not taken as moving ends: no contact.
  const std::vector<std::int32_t> none(sheet.neutral.size(), -1);
  CHECK(search.Find(none).empty());
  // The same scratch gives the same answer again (its path marks are reset).
  CHECK(search.Find(search.all_free).size() == kSlitLast - kSlitFirst - 1);
}

TEST_CASE("Expression contacts: skin pressed together without an opening is none", "[expression_contacts]") {
  const Sheet sheet = MakeSheet(false);
  ClosedSlitSearch search(sheet);
  CHECK(search.Find(search.all_free).empty());
}

TEST_CASE("Expression contacts: a surface between the pair blocks the contact", "[expression_contacts]") {
  // The slit sheet plus a flap of the same part standing in the slit: the
  // upper edge would pass through it.
  Sheet sheet = MakeSheet(true);
  const auto first_flap = static_cast<std::uint32_t>(sheet.neutral.size());
  sheet.neutral.emplace_back(kSlitFirst, kSlitRow + 0.5f, -1.0f);
  sheet.neutral.emplace_back(kSlitLast, kSlitRow + 0.5f, -1.0f);
  sheet.neutral.emplace_back(kSlitLast, kSlitRow + 0.5f, 1.0f);
  sheet.neutral.emplace_back(kSlitFirst, kSlitRow + 0.5f, 1.0f);
  sheet.triangles.push_back({first_flap, first_flap + 1, first_flap + 2});
  sheet.triangles.push_back({first_flap, first_flap + 2, first_flap + 3});
  // Joined to the sheet at one corner, far from the slit's middle.
  sheet.triangles.push_back({first_flap, Vertex(kSlitFirst, kSlitRow), Vertex(kSlitFirst, kSlitRow + 1)});
  facerig::ConnectedComponents(sheet.neutral.size(), sheet.triangles, sheet.component);
  REQUIRE(sheet.component[first_flap] == sheet.component[0]);
  ClosedSlitSearch search(sheet);
  CHECK(search.Find(search.all_free).empty());
}
