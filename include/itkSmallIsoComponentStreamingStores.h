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
#ifndef itkSmallIsoComponentStreamingStores_h
#define itkSmallIsoComponentStreamingStores_h

#include "itkIntTypes.h"
#include "SmallIsoComponentExport.h"

namespace itk
{
namespace SmallIsoComponentDetail
{

/** Copies \a bytes from \a source to \a destination, with streaming stores where SSE2 has
 * them: whole 64-byte cache lines only, the partial lines at both ends with ordinary
 * stores (a partly streamed line costs more than it saves). */
SmallIsoComponent_EXPORT void
StreamCopy(void * destination, const void * source, SizeValueType bytes);

/** Sets \a bytes at \a destination to zero, with streaming stores for the whole cache
 * lines where SSE2 has them. */
SmallIsoComponent_EXPORT void
StreamZero(void * destination, SizeValueType bytes);

/** Makes this thread's streaming stores visible before it hands its work back. */
SmallIsoComponent_EXPORT void
StreamFence();
} // namespace SmallIsoComponentDetail
} // end namespace itk

#endif
