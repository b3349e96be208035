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
#ifndef itkSmallIsoComponentUnionFind_h
#define itkSmallIsoComponentUnionFind_h

#include "itkSmallIsoComponentBitCount.h"

#include <atomic>
#include <utility>

namespace itk
{
namespace SmallIsoComponentDetail
{
/** \file
 * The one union-find of the engine: groups over an array of parents (a root is its own parent)
 * in which a group's root is always its smallest member, so the root a group ends with does not
 * depend on the order of its joins, nor on which thread made them. Runs, components and
 * summary nodes are all grouped through these functions. */

/** The root of \a node's group, halving the path on the way. */
template <typename T>
inline T
FindRoot(T * parent, T node)
{
  while (parent[node] != node)
  {
    parent[node] = parent[parent[node]];
    node = parent[node];
  }
  return node;
}

/** Joins the groups of \a a and \a b. When they were two, returns true with \a a the root kept
 * and \a b the root joined to it, so that the caller can add up what the roots carry. */
template <typename T>
inline bool
JoinRoots(T * parent, T & a, T & b)
{
  a = FindRoot(parent, a);
  b = FindRoot(parent, b);
  if (a == b)
  {
    return false;
  }
  if (b < a)
  {
    std::swap(a, b);
  }
  parent[b] = a;
  return true;
}

/** Joins the groups of \a a and \a b where nothing is added up at the roots: Rem's algorithm
 * with splicing walks both paths at once and stops as soon as they meet, which on runs, joined
 * mostly with their neighbours, is usually at once. */
template <typename T>
SMALLISO_ALWAYS_INLINE void
Join(T * parent, T a, T b)
{
  while (parent[a] != parent[b])
  {
    // The path whose parent is larger moves on, its node re-pointed to the smaller parent.
    if (parent[a] > parent[b])
    {
      if (parent[a] == a)
      {
        parent[a] = parent[b];
        return;
      }
      const T next = parent[a];
      parent[a] = parent[b];
      a = next;
    }
    else
    {
      if (parent[b] == b)
      {
        parent[b] = parent[a];
        return;
      }
      const T next = parent[b];
      parent[b] = parent[a];
      b = next;
    }
  }
}

/** FindRoot() over parents that other threads join at the same time (JoinShared()). */
template <typename T>
inline T
FindRootShared(std::atomic<T> * parent, T node)
{
  while (true)
  {
    const T up = parent[node].load(std::memory_order_relaxed);
    if (up == node)
    {
      return node;
    }
    const T upper = parent[up].load(std::memory_order_relaxed);
    if (upper != up)
    {
      parent[node].store(upper, std::memory_order_relaxed);
    }
    node = upper;
  }
}

/** Joins the groups of \a a and \a b while other threads join too: the larger root is put under
 * the smaller one only if it is still a root. */
template <typename T>
inline void
JoinShared(std::atomic<T> * parent, T a, T b)
{
  while (true)
  {
    a = FindRootShared(parent, a);
    b = FindRootShared(parent, b);
    if (a == b)
    {
      return;
    }
    if (a < b)
    {
      std::swap(a, b);
    }
    T expected = a;
    if (parent[a].compare_exchange_weak(expected, b, std::memory_order_relaxed))
    {
      return;
    }
  }
}
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
