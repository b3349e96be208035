#include "itkSmallIsoComponentImageFilter.h"
#include "itkImage.h"
#include <iostream>
int itkSmallIsoComponentImageFilterTest(int, char *[])
{
  using ImageType = itk::Image<unsigned char, 3>;
  auto image = ImageType::New();
  ImageType::SizeType size{{8, 8, 8}};
  image->SetRegions(size);
  image->Allocate();
  image->FillBuffer(0);
  ImageType::IndexType idx{{3,3,3}};
  image->SetPixel(idx, 100);
  auto filter = itk::SmallIsoComponentImageFilter<ImageType>::New();
  filter->SetInput(image);
  filter->SetIsoValue(50);
  filter->Update();
  filter->Print(std::cout);
  return filter->GetOutput()->GetPixel(idx) == 0 ? 0 : 1;
}
