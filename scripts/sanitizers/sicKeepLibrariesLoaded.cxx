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

// Linked into the tools of an AddressSanitizer build only (SmallIsoComponent_SANITIZER=address).
//
// LeakSanitizer looks for pointers to each block in the globals of the libraries still loaded when
// the process ends. A library that was unloaded before (Mesa's swrast_dri.so, which libGLX_mesa
// unloads when the rendering ends) takes its globals with it, and what they pointed to is then
// reported as leaked, with frames no symbolizer can name. This definition replaces dlclose for
// every library of the process (the executable exports it), so that nothing is unloaded and what a
// library still references is not counted as a leak; real leaks are still reported.

extern "C" int
dlclose(void * /* handle */)
{
  return 0;
}
