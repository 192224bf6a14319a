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

extern uint32_t _estack, _sdata, _edata, _sidata, _sbss, _ebss;

void Reset_Handler(void)
{
    uint32_t *src = &_sidata, *dst = &_sdata;
    while (dst < &_edata)
        *dst++ = *src++;
    for (dst = &_sbss; dst < &_ebss;)
        *dst++ = 0;
    (void)main();
    for (;;) {
    }
}

__attribute__((section(".isr_vector"), used)) static void (*const vectors[])(void) = {
    (void (*)(void))(&_estack), Reset_Handler, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, /* 16 system exceptions */
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, TIM2_IRQHandler,
};
