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
#ifndef itkSmallIsoComponentImageFilterBase_hxx
#define itkSmallIsoComponentImageFilterBase_hxx

#include "itkSmallIsoComponentImageFilterBase.h"
#include "itkMath.h"
#include "itkSmallIsoComponentBlockSummary.h"
#include <cmath>

namespace itk
{
template <typename TInputImage, typename TOutputImage>
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::SmallIsoComponentImageFilterBase()
{
  this->SetNumberOfRequiredOutputs(2);
  this->SetNthOutput(1, this->MakeOutput(1));
  this->InPlaceOff();
}

template <typename TInputImage, typename TOutputImage>
DataObject::Pointer
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::MakeOutput(DataObjectPointerArraySizeType idx)
{
  if (idx == 1)
  {
    return MaskImageType::New().GetPointer();
  }
  return Superclass::MakeOutput(idx);
}

template <typename TInputImage, typename TOutputImage>
auto
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::GetRemovedMask() -> MaskImageType *
{
  return itkDynamicCastInDebugMode<MaskImageType *>(this->ProcessObject::GetOutput(1));
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::SetMaximumComponentSize(SizeValueType size)
{
  if (m_MaximumComponentSize != size || m_UseMaximumComponentVolume)
  {
    m_MaximumComponentSize = size;
    m_UseMaximumComponentVolume = false;
    this->Modified();
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::SetMaximumComponentVolume(double volume)
{
  if (Math::NotExactlyEquals(m_MaximumComponentVolume, volume) || !m_UseMaximumComponentVolume)
  {
    m_MaximumComponentVolume = volume;
    m_UseMaximumComponentVolume = true;
    this->Modified();
  }
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::GetNumberOfComponents(SideEnum side) const
{
  return this->GetSideCounts(side).Components;
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::GetNumberOfRemovedComponents(SideEnum side) const
{
  return this->GetSideCounts(side).RemovedComponents;
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::GetNumberOfRemovedVoxels(SideEnum side) const
{
  return this->GetSideCounts(side).RemovedVoxels;
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::VerifyStatisticsSide(SideEnum side) const
{
  if (side != SideEnum::Above && side != SideEnum::Below)
  {
    itkExceptionMacro("Statistics are kept per side: ask for SideEnum::Above or SideEnum::Below, not " << side);
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::VerifyPreconditions()
#if !defined(ITKV4_COMPATIBILITY)
  const
#endif
{
  Superclass::VerifyPreconditions();
  if (std::isnan(m_IsoValue))
  {
    itkExceptionMacro("IsoValue is NaN; it must be a number (every voxel is compared with it).");
  }
  if (m_UseMaximumComponentVolume && !(m_MaximumComponentVolume >= 0.0))
  {
    itkExceptionMacro("MaximumComponentVolume is "
                      << m_MaximumComponentVolume << "; it must be a volume >= 0 in the image's physical units cubed.");
  }
  if (m_Side != SideEnum::Above && m_Side != SideEnum::Below && m_Side != SideEnum::Both)
  {
    itkExceptionMacro("Side is " << static_cast<int>(m_Side) << "; it must be Above, Below or Both.");
  }
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::AllocateOutputs()
{
  if (!m_GenerateRemovedMask)
  {
    // The mask keeps its geometry, gives back a buffer an earlier update may have left,
    // and is allocated with no voxels.
    MaskImageType *                    mask = this->GetRemovedMask();
    typename MaskImageType::RegionType none = mask->GetRequestedRegion();
    typename MaskImageType::SizeType   noSize;
    noSize.Fill(0);
    none.SetSize(noSize);
    mask->Initialize();
    mask->SetRequestedRegion(none);
  }
  Superclass::AllocateOutputs();
}

template <typename TInputImage, typename TOutputImage>
SizeValueType
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::ComputeEffectiveMaximumComponentSize(
  const typename InputImageType::SpacingType & spacing) const
{
  if (!m_UseMaximumComponentVolume)
  {
    return m_MaximumComponentSize;
  }
  double voxelVolume = 1.0;
  for (unsigned int a = 0; a < ImageDimension; ++a)
  {
    voxelVolume *= spacing[a];
  }
  return static_cast<SizeValueType>(
    SmallIsoComponentDetail::ComponentRules::MaximumSizeForVolume(m_MaximumComponentVolume, voxelVolume));
}

template <typename TInputImage, typename TOutputImage>
void
SmallIsoComponentImageFilterBase<TInputImage, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "IsoValue: " << m_IsoValue << std::endl;
  os << indent << "MaximumComponentSize: " << m_MaximumComponentSize << std::endl;
  os << indent << "MaximumComponentVolume: " << m_MaximumComponentVolume << std::endl;
  os << indent << "UseMaximumComponentVolume: " << (m_UseMaximumComponentVolume ? "On" : "Off") << std::endl;
  os << indent << "Side: " << m_Side << std::endl;
  os << indent << "FullyConnected: " << (m_FullyConnected ? "On" : "Off") << std::endl;
  os << indent << "GenerateRemovedMask: " << (m_GenerateRemovedMask ? "On" : "Off") << std::endl;
}
} // end namespace itk

#endif
