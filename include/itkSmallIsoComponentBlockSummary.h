/*=========================================================================
 *
 *  Copyright SmallIsoComponent contributors
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
#ifndef itkSmallIsoComponentBlockSummary_h
#define itkSmallIsoComponentBlockSummary_h

#include "itkSmallIsoComponentEnums.h"
#include "SmallIsoComponentExport.h"
#include <array>
#include <cstdint>
#include <map>
#include <vector>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** What decides a component's fate: K, the side(s) processed, the connectivity, and whether
 * the pixel type has a value on each side of the isovalue (a component whose other side has
 * no representable value is kept and counted as unrepairable). */
struct ComponentRules
{
  uint64_t                     MaximumComponentSize{ 20 };
  SmallIsoComponentEnums::Side Side{ SmallIsoComponentEnums::Side::Both };
  bool                         FullyConnected{ false };
  bool                         AnyAbove{ true };
  bool                         AnyBelow{ true };

  /** K for a maximum component volume: floor(volume / voxelVolume), with a relative tolerance of
   * 1e-12 so that a volume of exactly k voxels gives k despite rounding; saturates. */
  static uint64_t
  MaximumSizeForVolume(double volume, double voxelVolume);
};

/** Component counts of one side: how many, how many removed, their voxels, and the size
 * histogram (size -> number of components), small sizes in an array. */
class SmallIsoComponent_EXPORT SideTally
{
public:
  void
  Add(uint64_t size, bool removed);
  void
  Add(const SideTally & other);

  uint64_t
  GetComponents() const
  {
    return m_Components;
  }
  uint64_t
  GetRemovedComponents() const
  {
    return m_RemovedComponents;
  }
  uint64_t
  GetRemovedVoxels() const
  {
    return m_RemovedVoxels;
  }
  std::map<uint64_t, uint64_t>
  GetHistogram() const;

private:
  friend class BlockSummary;
  static constexpr uint64_t    SmallSizes = 256;
  uint64_t                     m_Components{ 0 };
  uint64_t                     m_RemovedComponents{ 0 };
  uint64_t                     m_RemovedVoxels{ 0 };
  std::vector<uint64_t>        m_Small;
  std::map<uint64_t, uint64_t> m_Large;
};

/** The statistics of the components that have been settled so far. ModifiedVoxels and
 * UnrepairableVoxels count what the component sizes decide: the voxels of removed components
 * (each once, also when a removed above component is removed again in the below pass) and the
 * voxels of small components kept for lack of a value on the other side. Voxels that get the
 * fallback value because every walk left the image are counted by the repair, not here. */
struct SmallIsoComponent_EXPORT ComponentTally
{
  SideTally Above;
  SideTally Below;
  uint64_t  ModifiedVoxels{ 0 };
  uint64_t  UnrepairableVoxels{ 0 };

  void
  Add(const ComponentTally & other);
};

/** A face layer of a BlockSummary as runs of voxels of one node along its rows (a row runs along the lower of
 * the face's two axes, rows in order along the higher): the runs of row r are
 * Runs[RowBegin[r]] .. Runs[RowBegin[r + 1] - 1], each from its Column to the next run's (the
 * last to the end of the row), the first at column 0. The faces of a summary cost what their
 * runs do, not what their voxels do. */
struct BlockFaceRun
{
  uint32_t Column;
  uint32_t Node;
};
struct BlockFaceLayer
{
  std::vector<SizeValueType> RowBegin; // rows + 1 entries; empty when the face is not held
  std::vector<BlockFaceRun>  Runs;

  /** Building a layer: BeginRow() before each row, AddVoxels() for its voxels from left to
   * right (voxels of the node of the run before them lengthen it), EndLayer() after the last. */
  void
  BeginRow()
  {
    RowBegin.push_back(Runs.size());
  }
  void
  AddVoxels(SizeValueType column, uint32_t node)
  {
    if (Runs.size() == RowBegin.back() || Runs.back().Node != node)
    {
      Runs.push_back({ static_cast<uint32_t>(column), node });
    }
  }
  void
  EndLayer()
  {
    RowBegin.push_back(Runs.size());
  }
};

/** \class BlockSummary
 * \brief What a box of a 3-D image tells about its components to the rest of the image: the
 * components that reach its faces, exactly enough to finish labelling, counting and deciding
 * them once the neighbouring boxes are known.
 *
 * A box is labelled on its own (every component of each side inside it, with its size); its
 * summary keeps, for each face that lies inside the image, the layer of voxels along that face
 * as the components they belong to, and for Side Both the below components each possibly small
 * above component touches. Merging the summaries of two boxes that share a face joins the
 * components that touch across it; a component that no longer reaches a face inside the image is
 * complete, so its size is final: it is counted, and decided (removed when it has at most K
 * voxels). For Side Both a removed above component joins the below components it touches, as the
 * below pass sees them (SPEC 5); a below component is final when it is complete and no above
 * component that may still be removed touches it. What stays in a summary is proportional to its
 * faces, not to its voxels.
 *
 * The same merge serves a sweep along the slowest axis (the streaming mode: the image so far,
 * merged with the next slab) and a tree over a grid of chunks (the chunked mode). Images of two
 * dimensions are boxes of depth one. Every node of a summary carries an identifier that the
 * caller can follow through merges (Resolution) to learn when and how its component was decided.
 *
 * Internal to the module.
 * \ingroup SmallIsoComponent
 */
class SmallIsoComponent_EXPORT BlockSummary
{
public:
  using IndexType = std::array<uint64_t, 3>;
  using NodeType = uint32_t;

  /** The fate of a node after a merge (or after Settle()). Kept and Removed are final. */
  enum class State : uint8_t
  {
    Open,    // not decided yet; Node is its node in the new summary
    Kept,    // stays as it is in this pass
    Removed, // removed in this pass
    NotAbove // (above pass of a below node) the node is not an above component
  };
  struct Resolution
  {
    State AbovePass{ State::NotAbove };
    State BelowPass{ State::Open };
    /** The node in the new summary: of the above component while AbovePass is Open, of the
     * below component (or group of them) while BelowPass is Open; NoNode otherwise. */
    NodeType Node{ NoNode };
  };
  static constexpr NodeType NoNode = 0xFFFFFFFFu;

  /** A summary of the box [begin, end) of an image of \a imageSize voxels, with \a rules, whose
   * components are given by the calls below and then Settle(). */
  BlockSummary(const IndexType &      imageSize,
               const IndexType &      begin,
               const IndexType &      end,
               const ComponentRules & rules);

  using FaceRun = BlockFaceRun;
  using FaceLayer = BlockFaceLayer;

  /** \name Building from a labelled box
   * The box's components are numbered 0..n-1 (AddComponent() in order). Each face inside the
   * image gets its layer (SetFaceLayer(): the component of every voxel along the face, the
   * lower of the two other axes fastest, or the same as runs), and for Side Both every pair of
   * an above component of at most K voxels and a below component it touches is given once or
   * more (AddTouching()). */
  /** @{ */
  NodeType
  AddComponent(bool above, uint64_t size);
  bool
  HasFace(unsigned int axis, bool upper) const;
  void
  SetFaceLayer(unsigned int axis, bool upper, const std::vector<NodeType> & layer);
  void
  SetFaceLayer(unsigned int axis, bool upper, FaceLayer layer);
  /** Whether AddTouching() is needed for an above component of this size. */
  bool
  NeedsTouching(uint64_t aboveSize) const;
  void
  AddTouching(NodeType above, NodeType below);
  /** Decides what the box alone decides. \a resolutions, if given, receives the fate of every
   * component added (indexed by its number). */
  void
  Settle(std::vector<Resolution> * resolutions = nullptr);
  /** @} */

  /** Merges \a lower and \a upper, two summaries of boxes that share a face (upper starts
   * where lower ends along one axis and both cover the same range along the others), into the
   * summary of their union. Each may be settled or fresh from its box (all its components
   * given, Settle() not called): the merge decides what Settle() would have, with the same
   * result. \a lowerResolutions and \a upperResolutions, if given, receive the fate of every
   * node of each. */
  static BlockSummary
  Merge(const BlockSummary &      lower,
        const BlockSummary &      upper,
        std::vector<Resolution> * lowerResolutions = nullptr,
        std::vector<Resolution> * upperResolutions = nullptr);

  /** The statistics of the components this summary (and the summaries merged into it) settled. */
  const ComponentTally &
  GetTally() const
  {
    return m_Tally;
  }

  /** Nodes still held: components that are open or not final yet. */
  SizeValueType
  GetNumberOfNodes() const
  {
    return m_Size.size();
  }
  /** Bytes held by the summary. */
  SizeValueType
  GetMemoryInBytes() const;

  /** \name Serialization (for moving summaries between processes) */
  /** @{ */
  std::vector<uint8_t>
  Serialize() const;
  static BlockSummary
  Deserialize(const uint8_t * data, SizeValueType bytes);
  /** @} */

private:
  BlockSummary() = default;

  /** The face of \a axis: index 2 * axis + upper. */
  static unsigned int
  FaceIndex(unsigned int axis, bool upper)
  {
    return 2 * axis + (upper ? 1 : 0);
  }
  /** The two axes spanning a face of \a axis, the faster first. */
  static std::array<unsigned int, 2>
  FaceAxes(unsigned int axis);
  uint64_t
  Extent(unsigned int axis) const
  {
    return m_End[axis] - m_Begin[axis];
  }
  SizeValueType
  FaceLayerSize(unsigned int axis) const;
  /** The width of the rows of the face of \a axis and their number. */
  SizeValueType
  FaceRowWidth(unsigned int axis) const;
  SizeValueType
  FaceRows(unsigned int axis) const;

  /** Decides, given the union-find \a parent over the nodes held in the working arrays
   * (m_Size, m_Above, m_Flipped of every node, valid at roots) and \a touching pairs, what
   * can be decided, and rebuilds this summary from the nodes that stay. */
  void
  SettleNodes(std::vector<NodeType> &                      parent,
              std::vector<std::pair<NodeType, NodeType>> & touching,
              std::vector<Resolution> *                    resolutions);
  /** Merge()'s steps: the axis along which \a upper follows \a lower (or an exception), the faces
   * of their union, and the joins of the components that touch across their shared face. */
  static unsigned int
  SharedFaceAxis(const BlockSummary & lower, const BlockSummary & upper);
  void
  SetUnionFaces(const BlockSummary & lower, const BlockSummary & upper, unsigned int axis);
  void
  JoinAcrossFace(const BlockSummary &                         lower,
                 const BlockSummary &                         upper,
                 unsigned int                                 axis,
                 std::vector<NodeType> &                      parent,
                 std::vector<std::pair<NodeType, NodeType>> & touching);
  /** SettleNodes()'s steps, over its working state. */
  struct Settling;
  void
  DecideAbovePass(Settling & settling);
  void
  JoinFlippedToTouching(Settling & settling);
  void
  DecideBelowPass(Settling & settling);
  void
  KeepOpenNodes(Settling & settling);
  void
  Resolve(Settling & settling, const std::vector<uint8_t> & wasAbove, std::vector<Resolution> & resolutions) const;

  IndexType      m_ImageSize{};
  IndexType      m_Begin{};
  IndexType      m_End{};
  ComponentRules m_Rules;
  /** Per node: voxels, side, and for below nodes the voxels of removed above components in it. */
  std::vector<uint64_t> m_Size;
  std::vector<uint8_t>  m_Above;
  std::vector<uint64_t> m_Flipped;
  /** Whether \a layer is a well-formed layer of the face of \a axis over nodes below \a nodes. */
  bool
  IsValidFaceLayer(unsigned int axis, const FaceLayer & layer, SizeValueType nodes) const;

  /** Layers of the faces inside the image (empty for the others), indexed by FaceIndex(). */
  std::array<FaceLayer, 6> m_Face;
  /** For Side Both: (above node, below node) pairs, the above node possibly small. */
  std::vector<std::pair<NodeType, NodeType>> m_Touching;
  ComponentTally                             m_Tally;
};
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
