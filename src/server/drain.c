/* drain.c — a listening socket that lets no new connection into its queue (drain.h): a
 * classic BPF filter on the socket, which Linux runs on every packet offered to it. */
#define _DEFAULT_SOURCE /* SO_ATTACH_FILTER */
#include <linux/filter.h>
#include <sys/socket.h>

#include "server/drain.h"

/* A TCP socket's filter sees the packet from its TCP header: the flags are byte 13. A child
 * socket keeps its listener's filter from its birth, and never sees a bare SYN. */
int tc_drain_refuse_new(int fd) {
    struct sock_filter syn_only[] = {
        BPF_STMT(BPF_LD | BPF_B | BPF_ABS, 13),          /* the flags */
        BPF_STMT(BPF_ALU | BPF_AND | BPF_K, 0x12),       /* SYN, ACK */
        BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, 0x02, 0, 1), /* a SYN alone: */
        BPF_STMT(BPF_RET | BPF_K, 0),                    /* dropped */
        BPF_STMT(BPF_RET | BPF_K, 0xffffffffu),          /* the rest kept whole */
    };
    struct sock_fprog prog = {(unsigned short)(sizeof syn_only / sizeof syn_only[0]), syn_only};
    return setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &prog, sizeof prog);
}
