/* SPDX-License-Identifier: MIT */
/*
 * Minimal start-up of the firmware example (example_isr.c, both builds),
 * so that it links as a real image would: copy .data, clear .bss, call
 * main; the vector table names the sampling interrupt, TIM2_IRQHandler,
 * which the example defines.
 */
#include <stdint.h>

int main(void);
void TIM2_IRQHandler(void);
void Reset_Handler(void);

/* Linker symbols: each marks an address, not an object of its own, so
 * they are declared as arrays (no object size is implied) and the extent
 * of a section is computed from their addresses as integers. Comparing
 * pointers into different objects, as `dst < &_edata` did, is undefined
 * in C (and cppcheck's comparePointers): a compiler may assume it never
 * differs from what the object model says. */
extern uint32_t _estack[], _sdata[], _edata[], _sidata[], _sbss[], _ebss[];

/* Words from @p start up to @p end (linker symbols), a part word counted
 * whole as the old `while (dst < end)` loop did, and 0 when end <= start
 * (an empty section, or symbols out of order: nothing to copy, rather
 * than a difference that wraps to 4 G words). Whole words are copied and
 * cleared, so the linker script must keep the four symbols 4-byte
 * aligned (example.ld says so next to them); then nothing is rounded. */
static uint32_t words(const uint32_t *start, const uint32_t *end)
{
    const uintptr_t s = (uintptr_t)start, e = (uintptr_t)end;
    return e > s ? (uint32_t)((e - s + sizeof(uint32_t) - 1) / sizeof(uint32_t)) : 0u;
}

void Reset_Handler(void)
{
    uint32_t i, n = words(_sdata, _edata);
    for (i = 0; i < n; i++)
        _sdata[i] = _sidata[i];
    n = words(_sbss, _ebss);
    for (i = 0; i < n; i++)
        _sbss[i] = 0;
    (void)main();
    for (;;) {
    }
}

__attribute__((section(".isr_vector"), used)) static void (*const vectors[])(void) = {
    (void (*)(void))_estack, Reset_Handler, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, /* 16 system exceptions */
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, TIM2_IRQHandler,
};
