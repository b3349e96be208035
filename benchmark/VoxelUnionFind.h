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
#ifndef VoxelUnionFind_h
#define VoxelUnionFind_h

// The textbook peer of the benchmark: one union-find node per voxel, union by size and
// path halving, face connectivity, a full labelling per side. It repairs like
// SmallIsoComponentImageFilter (walks along the axes on the values before the pass), so
// its output must equal the filter's; the benchmark checks that.

#include <cmath>
#include <cstdint>
#include <vector>

namespace VoxelUnionFind
{
template <typename T>
class Peer
{
public:
  /** Side Both: the above pass, then the below pass on its result. \a image is modified
   * in place; returns the number of voxels written. */
  std::size_t
  Run(T * image, const std::size_t size[3], double isoValue, std::size_t maximumSize)
  {
    m_Size[0] = size[0];
    m_Size[1] = size[1];
    m_Size[2] = size[2];
    m_Count = size[0] * size[1] * size[2];
    m_LowestAbove = static_cast<T>(std::ceil(isoValue));
    std::size_t written = this->Pass(image, true, maximumSize);
    written += this->Pass(image, false, maximumSize);
    return written;
  }

  std::size_t
  ExtraBytes() const
  {
    return (m_Parent.capacity() + m_ComponentSize.capacity() + m_Removed.capacity()) * sizeof(uint32_t) +
           m_Values.capacity() * sizeof(T);
  }

private:
  bool
  Above(T v) const
  {
    return v >= m_LowestAbove;
  }

  uint32_t
  Find(uint32_t v)
  {
    while (m_Parent[v] != v)
    {
      m_Parent[v] = m_Parent[m_Parent[v]];
      v = m_Parent[v];
    }
    return v;
  }

  void
  Unite(uint32_t a, uint32_t b)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a == b)
    {
      return;
    }
    if (m_ComponentSize[a] < m_ComponentSize[b])
    {
      std::swap(a, b);
    }
    m_Parent[b] = a;
    m_ComponentSize[a] += m_ComponentSize[b];
  }

  std::size_t
  Pass(T * image, bool side, std::size_t maximumSize)
  {
    const std::size_t nx = m_Size[0], ny = m_Size[1], nz = m_Size[2], plane = nx * ny;
    m_Parent.resize(m_Count);
    m_ComponentSize.assign(m_Count, 1);
    for (std::size_t i = 0; i < m_Count; ++i)
    {
      m_Parent[i] = static_cast<uint32_t>(i);
    }
    std::size_t i = 0;
    for (std::size_t z = 0; z < nz; ++z)
    {
      for (std::size_t y = 0; y < ny; ++y)
      {
        for (std::size_t x = 0; x < nx; ++x, ++i)
        {
          if (this->Above(image[i]) != side)
          {
            continue;
          }
          const auto v = static_cast<uint32_t>(i);
          if (x > 0 && this->Above(image[i - 1]) == side)
          {
            this->Unite(v, v - 1);
          }
          if (y > 0 && this->Above(image[i - nx]) == side)
          {
            this->Unite(v, static_cast<uint32_t>(i - nx));
          }
          if (z > 0 && this->Above(image[i - plane]) == side)
          {
            this->Unite(v, static_cast<uint32_t>(i - plane));
          }
        }
      }
    }
    m_Removed.clear();
    for (std::size_t j = 0; j < m_Count; ++j)
    {
      if (this->Above(image[j]) == side && m_ComponentSize[this->Find(static_cast<uint32_t>(j))] <= maximumSize)
      {
        m_Removed.push_back(static_cast<uint32_t>(j));
      }
    }
    // Values first, then writes: the walks read the image before the pass.
    m_Values.resize(m_Removed.size());
    const std::ptrdiff_t stride[3] = { 1, static_cast<std::ptrdiff_t>(nx), static_cast<std::ptrdiff_t>(plane) };
    for (std::size_t r = 0; r < m_Removed.size(); ++r)
    {
      const std::size_t v = m_Removed[r];
      const std::size_t coordinate[3] = { v % nx, (v / nx) % ny, v / plane };
      double            sum = 0.0;
      unsigned int      found = 0;
      for (unsigned int axis = 0; axis < 3; ++axis)
      {
        for (int direction = -1; direction <= 1; direction += 2)
        {
          std::ptrdiff_t c = static_cast<std::ptrdiff_t>(coordinate[axis]) + direction;
          std::ptrdiff_t w = static_cast<std::ptrdiff_t>(v) + direction * stride[axis];
          for (; c >= 0 && c < static_cast<std::ptrdiff_t>(m_Size[axis]); c += direction, w += direction * stride[axis])
          {
            if (this->Above(image[w]) != side)
            {
              sum += static_cast<double>(image[w]);
              ++found;
              break;
            }
          }
        }
      }
      const double fallback = side ? static_cast<double>(m_LowestAbove) - 1.0 : static_cast<double>(m_LowestAbove);
      m_Values[r] = static_cast<T>(found > 0 ? std::floor(sum / found + 0.5) : fallback);
    }
    for (std::size_t r = 0; r < m_Removed.size(); ++r)
    {
      image[m_Removed[r]] = m_Values[r];
    }
    return m_Removed.size();
  }

  std::size_t           m_Size[3]{};
  std::size_t           m_Count{ 0 };
  T                     m_LowestAbove{};
  std::vector<uint32_t> m_Parent;
  std::vector<uint32_t> m_ComponentSize;
  std::vector<uint32_t> m_Removed;
  std::vector<T>        m_Values;
};
} // namespace VoxelUnionFind

#endif
