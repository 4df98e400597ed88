/* stc12cl.h: the STC12C5A60S2 in uCsim's s51 (-t STC12): the 1T core and the chip's own peripherals. */
#ifndef STC12CL_HEADER
#define STC12CL_HEADER

#include <stdint.h>
#include "uc52cl.h"
#include "timer0cl.h"
#include "itsrccl.h"

class cl_stc12hw;

/* The 1T core (datasheet, "Instruction set summary", the STC12 column): clocks an opcode,
 * not 12-clock machine cycles; the 8052's 256 B of internal RAM (no timer 2: the STC12 has none);
 * not 12-clock machine cycles; interrupts by IP/IPH in four levels (datasheet, "Interrupt
 * priority": IPH at 0xB7), the highest pending one first, then the polling order. */
class cl_stc12: public cl_uc52
{
 public:
 class cl_stc12hw *hw;
  class cl_hw *t0, *t1;
  class cl_memory_cell *c_ie, *c_tcon, *c_scon, *c_adc, *c_pcon, *c_ccon,
    *c_cmod, *c_ccapm0, *c_ccapm1;
  bool in_inst;                 /* the opcode's clocks are charged: the handlers' ticks are not */
  uint64_t lag;                 /* clocks the core ran that the peripherals have not been given */
  uint64_t room;                /* how far they may lag: nothing they do shows before (0: none) */
  bool stale;                   /* an SFR was written: room is to be taken again */
  bool it_dirty;                /* an interrupt's flag, enable or level may have changed */
  bool every;                   /* STC12_EVERY_INSTRUCTION: the peripherals ticked at each one */
  cl_stc12(struct cpu_entry *Itype, class cl_sim *asim);
  void clocks(int n);
  void catch_up(void);
  uint64_t quiet(void);
  bool touches_hw(uint8_t op);
  virtual void mk_hw_elements(void);
  virtual int clock_per_cycle(void) { return 1; }
  virtual int tickt(t_mem code);
  virtual int tick(int cycles);
  virtual int tick_hw(int cycles);
  virtual int exec_inst(void);
  virtual int do_inst(int step);
  virtual bool fetch(t_mem *code);
  virtual int idle_pd(void);
  virtual int priority_of(uchar nuof_it);
  virtual int do_interrupt(void);
  virtual int accept_it(class it_level *il);
  virtual void reset(void);
};

/* timer 0/1 counting SYSCLK/12, or SYSCLK with AUXR.T0x12/T1x12 (datasheet, "AUXR") */
class cl_stc12_timer: public cl_timer0
{
 public:
  int sub;
  class cl_memory_cell *auxr;
  cl_stc12_timer(class cl_uc *auc, int aid, const char *aid_string):
    cl_timer0(auc, aid, aid_string), sub(0), auxr(NULL) {}
  virtual int tick(int cycles);
  uint64_t room(void);
};

/* an interrupt source whose enable is its own register's bit (the PCA's ECF, ECCFn) */
class cl_stc12_it: public cl_it_src
{
 public:
  class cl_memory_cell *en_cell;
  t_mem en_mask;
  cl_stc12_it(cl_uc *auc, class cl_memory_cell *src, t_mem src_mask, class cl_memory_cell *en,
              t_mem aen_mask, t_addr vector, const char *name, int prio_bit):
    cl_it_src(auc, prio_bit, src, 0, src, src_mask, vector, false, false, name, 7),
    en_cell(en), en_mask(aen_mask) { ie_mask= prio_bit; }
  virtual bool enabled(void) { return (en_cell->get() & en_mask) != 0; }
};

#define STC12_VECTORS 8
struct stc12_ev { uint64_t clock; uint8_t kind; uint32_t value; };

/* PCA, ADC, UART 1 on the BRT, IAP EEPROM, watchdog, port modes, low-voltage flag, and the
 * lock-step link to the host's plant */
class cl_stc12hw: public cl_hw
{
 public:
  cl_stc12hw(class cl_uc *auc);
  virtual int init(void);
  virtual void added_to_uc(void);
  virtual int tick(int cycles);
  virtual void write(class cl_memory_cell *cell, t_mem *val);
  virtual void reset(void) {}
  void chip_reset(t_mem pcon_before);  /* the datasheet's reset values, after the core's */
  bool linked(void) { return fin != NULL; }   /* in lock step with the host's plant */
  bool powered;                 /* a reset after the power-on's keeps PCON's POF and LVDF */
  void inst_begin(t_addr pc, uint64_t lag);
  void isr_enter(t_addr vector, uint64_t lag);
  void isr_leave(uint64_t lag);
  uint64_t quiet(void);
  int stall;                    /* clocks the CPU is held (IAP) before the next instruction */
  bool reset_due;               /* the watchdog overflowed: reset before the next instruction */
  bool pin_reset;               /* the reset pin: the same */
  bool hung;                    /* the main loop hung (STC12_EV_HANG) */
 private:
  class cl_address_space *sfr, *xram;
  class cl_memory_cell *c_ccon, *c_cmod, *c_cl, *c_ch, *c_ccapm[2], *c_ccapl[2], *c_ccaph[2],
    *c_pwm[2], *c_adc, *c_res, *c_resl, *c_scon, *c_sbuf, *c_brt, *c_auxr, *c_wdt, *c_pcon,
    *c_iap_data, *c_iap_ah, *c_iap_al, *c_iap_cmd, *c_iap_trig, *c_iap_contr,
    *c_p1, *c_p3, *c_p2, *c_sp, *c_p1m0, *c_p1m1, *c_p3m0, *c_p3m1, *c_th1, *c_tmod;
  class cl_hw *port[4];
  uint64_t now;                 /* SYSCLK clocks since power-on */
  int pca_sub;                  /* clocks towards the next PCA count */
  uint8_t ccp0_prev;            /* CCP0 pin level, for its falling edge */
  uint64_t adc_done;            /* 0: no conversion running */
  uint16_t adc_in[8];
  uint64_t tx_done;             /* 0: the transmitter idle */
  uint64_t rx_at;               /* 0: no frame arriving; else its sample end */
  uint8_t rx_byte, rx_ok;
  uint64_t wdt_count;
  uint8_t iap_seq;              /* the 0x5A of the trigger pair seen */
  uint8_t eeprom[1024];
  uint16_t keys;
  uint8_t p2_latch;
  uint64_t p3_high_at, p1_high_at;   /* a pulse's pin back high */
  /* the link */
  FILE *fin, *fout;
  uint64_t slot_end;
  struct stc12_ev *ev;
  unsigned n_ev, i_ev, cap_ev;
  t_addr pass_pc;
  uint16_t watch_addr[8];
  uint8_t watch_len[8], n_watch;
  uint8_t resets, cause;
  uint16_t passes;
  uint64_t pass_start;
  uint32_t pass_max, pass_sum, step_max;
  uint8_t pass_adc, pass_iap, max_adc, max_iap;
  uint8_t tx_log[64 * 12];
  unsigned n_tx;
  struct { uint32_t count, max, own_max; uint64_t sum; } vec[STC12_VECTORS];
  struct { uint64_t t, child; int v; } isr_stack[8];
  int isr_depth;
  bool quit;

  bool sweep;                   /* STC12_EV_WHEEL_SWEEP */
  uint64_t sweep_at;
  uint32_t sweep_off, sweep_k;
  uint16_t early;
  uint8_t sp_max;               /* the highest SP since the first pass */
  /* the pass profile (STC12_PROFILE names its file): each instruction of the pass running, its
   * PC, SP and start clock in the pass; kept for the longest pass [0], control step [1],
   * other pass from the first second on [2], and pass that ran the code at STC12_PROFILE_AT [3] */
  struct prof_rec { uint16_t pc; uint8_t sp; uint32_t t; };
  FILE *prof_out;
  struct prof_rec *prof_cur, *prof_keep[4];
  uint32_t prof_n, prof_cap, prof_keep_n[4], prof_keep_len[4];
  uint64_t prof_keep_start[4];
  uint8_t prof_keep_adc[4];
  long prof_at;                 /* -1: none */
  bool prof_hit;                /* the pass running reached prof_at */
  void prof_pass_end(uint32_t d);
  void prof_write(void);
  unsigned pca_clocks(void);
  uint16_t strong(void);
  unsigned pwm1(void);
  void advance(uint64_t to);
  void apply(const struct stc12_ev *e);
  void link_slot(void);
  void link_config(void);
  void link_end(void);
  unsigned bit_clocks(void);
  void uart_tx(uint8_t b);
  void iap(void);
  void port_pins(int n, t_mem v);
  void keypad(void);
  uint64_t rd(int n);
  void wr(uint64_t v, int n);
};

#endif
