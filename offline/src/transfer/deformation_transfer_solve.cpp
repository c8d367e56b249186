#include "transfer/deformation_transfer_impl.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <thread>

namespace facerig {

namespace {

// The free rows of a solution (free_index >= 0) into out.
void WriteSolution(std::span<const std::int32_t> free_index, const Eigen::MatrixXd& solution,
                   std::vector<glm::vec3>& out) {
  for (std::size_t v = 0; v < free_index.size(); ++v) {
    const std::int32_t f = free_index[v];
    if (f < 0) continue;
    out[v] = glm::vec3(static_cast<float>(solution(f, 0)), static_cast<float>(solution(f, 1)),
                       static_cast<float>(solution(f, 2)));
  }
}

}  // namespace

double DeformationTransferData::Impl::Solve(std::span<const glm::vec3> expression,
                                           std::vector<glm::vec3>& out, Scratch& scratch) const {
  const std::size_t n = target_neutral.size();
  const Eigen::Index free_count = coupling.rows();
  scratch.contacts.clear();
  // Right-hand side U^T S, accumulated per vertex (x y z contiguous).
  scratch.desired.resize(triangles.size());
  scratch.accumulated.assign(3 * n, 0.0);
  double* acc = scratch.accumulated.data();
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    const Mat32 desired = DesiredEdges(j, expression);
    scratch.desired[j] = desired;
    const Eigen::Matrix3d h = desired * triangle_data[j].rhs_operator;
    for (int a = 0; a < 3; ++a) {
      double* target = acc + 3 * static_cast<std::size_t>(triangles[j][static_cast<std::size_t>(a)]);
      target[0] += h(0, a);
      target[1] += h(1, a);
      target[2] += h(2, a);
    }
  }
  out.resize(n);
  if (still_fraction > 0.0) {
    SolveStillPinned(expression, acc, out, scratch);
    return Residual(out, scratch);
  }
  const auto anchor_count = static_cast<Eigen::Index>(anchors.size());
  scratch.anchor_positions.resize(anchor_count, 3);
  for (Eigen::Index i = 0; i < anchor_count; ++i) {
    const glm::vec3 p = AnchorPosition(anchors[static_cast<std::size_t>(i)], expression);
    scratch.anchor_positions.row(i) << p.x, p.y, p.z;
  }
  if (free_count > 0) {
    FillFreeRhs(free_index, free_count, acc, expression, scratch.rhs);
    scratch.rhs -= coupling * scratch.anchor_positions;
    scratch.solution = solver.solve(scratch.rhs);
    WriteSolution(free_index, scratch.solution, out);
  }
  for (Eigen::Index i = 0; i < anchor_count; ++i) {
    out[anchors[static_cast<std::size_t>(i)]] =
        glm::vec3(static_cast<float>(scratch.anchor_positions(i, 0)),
                  static_cast<float>(scratch.anchor_positions(i, 1)),
                  static_cast<float>(scratch.anchor_positions(i, 2)));
  }
  for (const std::vector<std::uint32_t>& part : floating_parts) {
    PlaceFloatingPart(part, expression, out);
  }
  return Residual(out, scratch);
}

void DeformationTransferData::Impl::FillFreeRhs(std::span<const std::int32_t> vertex_free_index,
                                                Eigen::Index free_count, const double* accumulated,
                                                std::span<const glm::vec3> expression,
                                                Eigen::MatrixXd& rhs) const {
  rhs.resize(free_count, 3);
  for (std::size_t v = 0; v < vertex_free_index.size(); ++v) {
    const std::int32_t f = vertex_free_index[v];
    if (f < 0) continue;
    rhs.row(f) << accumulated[3 * v], accumulated[3 * v + 1], accumulated[3 * v + 2];
    if (prior > 0.0) {
      const glm::vec3 p = AnchorPosition(static_cast<std::uint32_t>(v), expression);
      rhs.row(f) += prior * Eigen::RowVector3d(p.x, p.y, p.z);
    }
  }
}

void DeformationTransferData::Impl::SolveStillPinned(std::span<const glm::vec3> expression,
                                                     const double* accumulated,
                                                     std::vector<glm::vec3>& out,
                                                     Scratch& scratch) const {
  const float largest2 = PinStillVertices(expression, scratch);
  if (rigid_tolerance > 0.0) PinRigidMotions(expression, out, scratch);
  PinFloatingParts(scratch);
  const std::int32_t free_count = IndexFreeVertices(expression, out, scratch);
  if (free_count > 0) {
    AssembleFreeRows(expression, accumulated, free_count, out, scratch);
    AddContacts(expression, largest2, out, scratch);
    SolveFreeRows(free_count, out, scratch);
  }
  for (std::uint32_t c : scratch.floating_components) {
    PlaceFloatingPart(component_members[c], expression, out);
  }
}

float DeformationTransferData::Impl::PinStillVertices(std::span<const glm::vec3> expression,
                                                      Scratch& scratch) const {
  const std::size_t n = target_neutral.size();
  float largest2 = 0.0f;
  for (std::size_t v = 0; v < n; ++v) {
    const glm::vec3 d = expression[v] - source_neutral[v];
    largest2 = std::max(largest2, d.x * d.x + d.y * d.y + d.z * d.z);
  }
  const auto still2 = static_cast<float>(still_fraction * still_fraction) * largest2;
  scratch.pinned.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    const glm::vec3 d = expression[v] - source_neutral[v];
    scratch.pinned[v] = is_static_anchor[v] || d.x * d.x + d.y * d.y + d.z * d.z <= still2;
  }
  return largest2;
}

void DeformationTransferData::Impl::PinFloatingParts(Scratch& scratch) const {
  // A part with nothing pinned moves as a whole: pin its gauge, place it after the solve.
  scratch.floating_components.clear();
  for (std::size_t c = 0; c < component_members.size(); ++c) {
    const std::vector<std::uint32_t>& part = component_members[c];
    if (std::none_of(part.begin(), part.end(), [&](std::uint32_t v) { return scratch.pinned[v]; })) {
      scratch.pinned[component_gauge[c]] = 1;
      scratch.floating_components.push_back(static_cast<std::uint32_t>(c));
    }
  }
}

std::int32_t DeformationTransferData::Impl::IndexFreeVertices(std::span<const glm::vec3> expression,
                                                              std::vector<glm::vec3>& out,
                                                              Scratch& scratch) const {
  const std::size_t n = target_neutral.size();
  scratch.free_index.assign(n, -1);
  std::int32_t free_count = 0;
  for (std::size_t v = 0; v < n; ++v) {
    if (scratch.pinned[v] == kPinnedRigid) {
      continue;  // placed by PinRigidMotions
    } else if (scratch.pinned[v]) {
      out[v] = AnchorPosition(static_cast<std::uint32_t>(v), expression);
    } else {
      scratch.free_index[v] = free_count++;
    }
  }
  return free_count;
}

void DeformationTransferData::Impl::AssembleFreeRows(std::span<const glm::vec3> expression,
                                                     const double* accumulated, std::int32_t free_count,
                                                     std::span<const glm::vec3> out,
                                                     Scratch& scratch) const {
  FillFreeRhs(scratch.free_index, free_count, accumulated, expression, scratch.rhs);
  scratch.triplets.clear();
  for (Eigen::Index column = 0; column < full_system.outerSize(); ++column) {
    const std::int32_t free_column = scratch.free_index[static_cast<std::size_t>(column)];
    const glm::vec3 p = out[static_cast<std::size_t>(column)];
    for (Eigen::SparseMatrix<double>::InnerIterator it(full_system, column); it; ++it) {
      const std::int32_t free_row = scratch.free_index[static_cast<std::size_t>(it.row())];
      if (free_row < 0) continue;
      if (free_column >= 0) {
        scratch.triplets.emplace_back(free_row, free_column, it.value());
      } else {
        scratch.rhs.row(free_row) -= it.value() * Eigen::RowVector3d(p.x, p.y, p.z);
      }
    }
  }
  if (prior > 0.0) {
    for (std::int32_t f = 0; f < free_count; ++f) scratch.triplets.emplace_back(f, f, prior);
  }
}

void DeformationTransferData::Impl::AddContacts(std::span<const glm::vec3> expression, float largest2,
                                                std::span<const glm::vec3> out,
                                                Scratch& scratch) const {
  // Contacts: w |x_moving - x_partner - offset|^2, a pinned end on the right-hand
  // side; offset 0 when they close.
  if (contact_finder) {
    contact_finder->Find(expression, std::sqrt(largest2), scratch.free_index, scratch.contacts,
                         scratch.contact_scratch);
  }
  for (const OpeningContact& contact : scratch.contacts) {
    const std::int32_t a = scratch.free_index[contact.moving];  // free: Find's moving ends are
    const std::int32_t b = scratch.free_index[contact.partner];
    const glm::vec3 offset =
        close_contacts ? glm::vec3(0.0f) : static_cast<float>(displacement_scale) * contact.offset;
    const Eigen::RowVector3d weighted_offset = contact_weight * Eigen::RowVector3d(offset.x, offset.y, offset.z);
    scratch.triplets.emplace_back(a, a, contact_weight);
    scratch.rhs.row(a) += weighted_offset;
    if (b >= 0) {
      scratch.triplets.emplace_back(b, b, contact_weight);
      scratch.triplets.emplace_back(a, b, -contact_weight);
      scratch.triplets.emplace_back(b, a, -contact_weight);
      scratch.rhs.row(b) -= weighted_offset;
    } else {
      const glm::vec3 p = out[contact.partner];  // pinned, placed above
      scratch.rhs.row(a) += contact_weight * Eigen::RowVector3d(p.x, p.y, p.z);
    }
  }
}

void DeformationTransferData::Impl::SolveFreeRows(std::int32_t free_count, std::vector<glm::vec3>& out,
                                                  Scratch& scratch) const {
  scratch.system.resize(free_count, free_count);
  scratch.system.setFromTriplets(scratch.triplets.begin(), scratch.triplets.end());
  scratch.solver.compute(scratch.system);
  if (scratch.solver.info() != Eigen::Success) {
    throw TransferSolverError("deformation transfer: the sparse Cholesky factorization of " +
                              std::to_string(free_count) + " unknowns failed");
  }
  scratch.solution = scratch.solver.solve(scratch.rhs);
  WriteSolution(scratch.free_index, scratch.solution, out);
}

void DeformationTransferData::Impl::PlaceFloatingPart(std::span<const std::uint32_t> part,
                                                      std::span<const glm::vec3> expression,
                                                      std::vector<glm::vec3>& out) const {
  // Exact least-squares optimum: a free part's gradient energy does not depend
  // on its translation.
  glm::dvec3 current(0.0);
  glm::dvec3 wanted(0.0);
  for (std::uint32_t v : part) {
    current += glm::dvec3(out[v]) - glm::dvec3(target_neutral[v]);
    wanted += glm::dvec3(expression[v]) - glm::dvec3(source_neutral[v]);
  }
  const glm::vec3 shift((wanted * displacement_scale - current) / static_cast<double>(part.size()));
  for (std::uint32_t v : part) out[v] += shift;
}

double DeformationTransferData::Impl::Residual(std::span<const glm::vec3> out,
                                               const Scratch& scratch) const {
  // sqrt(sum_j w_j |(E(X) - D) W|_F^2 / sum_j w_j), with w W W^T =
  // rhs_operator's right 2x2 block (B = [-1 1 0; -1 0 1]).
  double energy = 0.0;
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    const Mat32 diff = Edges(out, triangles[j]) - scratch.desired[j];
    const Eigen::Matrix2d weighted_metric = triangle_data[j].rhs_operator.rightCols<2>();
    energy += (diff * weighted_metric * diff.transpose()).trace();
  }
  return std::sqrt(std::max(0.0, energy) / total_weight);
}

double SolveDeformationTransfer(const DeformationTransferData& data,
                                std::span<const glm::vec3> source_expression,
                                std::vector<glm::vec3>& target_expression) {
  if (!data.impl) throw MeshInputError("data", "not precomputed");
  CheckPositions(source_expression, data.vertex_count, "source expression");
  DeformationTransferData::Impl::Scratch scratch;
  const double residual = data.impl->Solve(source_expression, target_expression, scratch);
  return residual;
}

}  // namespace facerig
