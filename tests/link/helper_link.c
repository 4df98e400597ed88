/* helper_link.c: see helper_link.h. */
#include <string.h>
#include "helper_link.h"
#include "hal_host.h"
#include "app.h"

uint64_t link_t_ms;

void link_start_at(double pressure_ma)
{
    hal_host_reset();
    hal_init();
    link_t_ms = 0;
    hal_host_io.adc[HAL_ADC_PRESSURE] = LINK_MA(pressure_ma);
    hal_host_io.adc[HAL_ADC_LEVEL] = LINK_MA(20.0);
    hal_host_io.sections = 0x3F;
    app_init();
}

void link_start(void)
{
    link_start_at(4.0);
}

void link_power_cycle(void)
{
    static uint8_t kept[HAL_EEPROM_SIZE];
    uint16_t pressure = hal_host_io.adc[HAL_ADC_PRESSURE];
    memcpy(kept, hal_host_eeprom(), sizeof kept);
    hal_host_reset();
    memcpy(hal_host_eeprom(), kept, sizeof kept);
    hal_init();
    link_t_ms = 0;
    hal_host_io.adc[HAL_ADC_PRESSURE] = pressure;
    hal_host_io.adc[HAL_ADC_LEVEL] = LINK_MA(20.0);
    hal_host_io.sections = 0x3F;
    app_init();
}

void link_run_ms(uint32_t ms)
{
    for (uint32_t i = 0; i < ms; i++) {
        link_t_ms++;
        hal_host_set_time_ns(link_t_ms * 1000000ull);
        app_poll();
    }
}

void link_send(const char *s)
{
    while (*s)
        hal_host_uart_rx_push((uint8_t)*s++);
}

size_t link_read_line(char *buf, size_t n)
{
    size_t len = 0;
    int b;
    while ((b = hal_host_uart_tx_pop()) >= 0 && b != '\n')
        if (len < n - 1)
            buf[len++] = (char)b;
    buf[len] = 0;
    return len;
}
