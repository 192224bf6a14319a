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

/* Words from @p start up to @p end (linker symbols, 4-byte aligned). */
static uint32_t words(const uint32_t *start, const uint32_t *end)
{
    return (uint32_t)(((uintptr_t)end - (uintptr_t)start) / sizeof(uint32_t));
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
