#pragma once
// Layering-test fixture.
